#version 450
// The path-traced reference's majorant grid (reference_tracer.h): per coarse cell of REF_MAJORANT_CELL^3
// modeling voxels, a bound of the up-rez density anywhere in the cell, from the modeling data alone.
// The trilinear filter blends a texel with its neighbours, so each cell reads one texel beyond its own on
// every side. The bound (cloud_common.glsl's uprez_density_from): the value erosion never raises the
// profile, so d0 <= profile x density scale <= max(r) x max(b) = m <= 1; the sharpening pow(d0, 0.3..0.6)
// gives at most m^0.3, and the near-camera wispy softening pow(d, 0.5..1) at most m^0.15. Dissipation
// only lowers the profile. The tracer multiplies by the instance's density and the extinction.
#extension GL_GOOGLE_include_directive : require
#include "shared/reference_params.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(set = 0, binding = REF_BINDING_MODELING_IN) uniform sampler3D modeling;
layout(set = 0, binding = REF_BINDING_MAJORANT_OUT, r32f) uniform writeonly image3D majorant;
layout(push_constant) uniform Push { ReferenceMajorantPush pc; };

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(c, pc.cells.xyz))) return;
  ivec3 dims = textureSize(modeling, 0);
  ivec3 lo = max(c * REF_MAJORANT_CELL - 1, ivec3(0));
  ivec3 hi = min(c * REF_MAJORANT_CELL + REF_MAJORANT_CELL, dims - 1);
  float r = 0.0, b = 0.0;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        vec3 m = texelFetch(modeling, ivec3(x, y, z), 0).rgb;
        r = max(r, m.r);
        b = max(b, m.b);
      }
  float m = clamp(r, 0.0, 1.0) * clamp(b, 0.0, 1.0);
  imageStore(majorant, c, vec4(m > 0.0 ? pow(m, 0.15) : 0.0));
}
