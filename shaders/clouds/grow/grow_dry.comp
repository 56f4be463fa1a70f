#version 450
// Cloud-formation solver, stage 4 (solver.cpp's dry; a decaying cloud): from the drying start the vapour relaxes
// down toward a fraction of the ambient profile. The host records it only while drying.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, vapour)
GROW_VEC4S(2, ambient)  // per level: theta0, exner, pressure, qv0

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  float target = P.forces.y * ambient[grow_coords(id, P.dims.xyz).y].w;
  float qv = vapour[id];
  if (qv <= target) return;
  vapour[id] = qv - (qv - target) * P.forces.x;
}
