#version 450
// What the march reads of the light grids at a sample, gathered per voxel of each instance's grid once the grids
// change (issue 23): x, y the summed density x world metres that the other instances' clouds put between the voxel
// and the sun (x) and the sky straight up (y) (other_instances_depth), z the voxel's own sky sum (the grid's y),
// w its own sum away from the sun (the grid's w). The march then fetches this once per sample where it fetched the
// grid and, for every other instance, transformed the point, clipped two rays to that instance's box and fetched
// its grid twice: on lavapipe the other instances' loop was a third of the march inside the storm cloud (lair).
// Between voxels the other instances' shadow is interpolated at the instance's own grid spacing.
// Same layout as the light grid (instance i in z slab i). pc.region: x instance, y first level (grid y), z level
// count, w first z layer; pc.grid: z z layers per instance, w z layers written. One work group in z
// (runtime_int in light_grid_lookup.glsl): a thread's level and layer come from its y.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = CLOUD_BINDING_LIGHT_GRID) uniform sampler3D light_grid_tex;
layout(set = 0, binding = CLOUD_BINDING_LOCAL_OUT, rgba16f) uniform writeonly image3D local_out;
layout(push_constant) uniform Push { CloudLightGridPush pc; };

#include "clouds/light_grid_lookup.glsl"

void main() {
  int layers = int(pc.grid.z), written = int(pc.grid.w);
  ivec3 size = ivec3(textureSize(light_grid_tex, 0).xy, layers);
  int row = int(gl_GlobalInvocationID.y);
  if (int(gl_GlobalInvocationID.x) >= size.x || written <= 0 || row >= written * int(pc.region.z)) return;
  ivec3 id = ivec3(gl_GlobalInvocationID.x, int(pc.region.y) + row / written, int(pc.region.w) + row % written);
  if (id.y >= size.y || id.z >= layers) return;
  int i = int(pc.region.x);
  ivec3 texel = id + ivec3(0, 0, i * layers);
  CloudInstanceParams inst = P.instances[i];
  vec3 cell = (inst.bounds_max.xyz - inst.bounds_min.xyz) / vec3(size);
  vec3 origin = inst.bounds_min.xyz + (vec3(id) + 0.5) * cell;
  vec3 world = (inverse(inst.world_to_asset) * vec4(origin, 1.0)).xyz;
  vec4 own = texelFetch(light_grid_tex, texel, 0);
  imageStore(local_out, texel, vec4(other_instances_depth(i, world), own.y, own.w));
}
