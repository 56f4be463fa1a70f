#version 450
// The march's inputs, the modeling image (RGBA8, the bake's modeling.nvdf, bake.cpp): r the dimensional profile
// from the distance and the voxel's own ramp depth (field.h's profile_from_field: saturate(-sdf / depth) ^
// exponent, the distance clamped to the field's range as the bake's is), g the detail type and b the density
// scale sampled from the cells (trilinear, clamped to 0..1), a the coverage threshold; each rounded to the nearest
// of 255 steps as the bake's lround.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Sdf { float sdf[]; };
layout(set = 0, binding = 2, std430) readonly buffer Depth { float depth[]; };
layout(set = 0, binding = 3, std430) readonly buffer Attributes { vec4 attributes[]; };
layout(set = 0, binding = GROWN_BINDING_MODELING_IMAGE, rgba8) uniform writeonly image3D modeling_image;

GROWN_TRILINEAR(sample_type, attributes, .x)
GROWN_TRILINEAR(sample_density, attributes, .y)

float unorm8(float x) { return floor(clamp(x, 0.0, 1.0) * 255.0 + 0.5) / 255.0; }

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  ivec3 v = grown_coords(id, P.voxels.xyz);
  float d = clamp(sdf[id], P.field.x, P.field.y);
  float t = clamp(-d / depth[id], 0.0, 1.0);
  float profile = P.profile.w + runtime_zero() == 1.0 ? t : pow(t, P.profile.w);
  vec3 p = grown_cell_position(v);
  float type = clamp(sample_type(P.cells.xyz, p), 0.0, 1.0);
  float density = clamp(sample_density(P.cells.xyz, p), 0.0, 1.0);
  imageStore(modeling_image, v, vec4(unorm8(profile), unorm8(type), unorm8(density), unorm8(P.coverage.x)));
}
