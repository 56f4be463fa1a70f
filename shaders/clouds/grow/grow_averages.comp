#version 450
// Cloud-formation solver, stage 7 (solver.cpp's step, after the projection): the exponential average of the local
// change of cloud water d(qc)/dt (kg/kg/s), > 0 where the cloud grows into the air; keeps qc for the next step.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, water)
GROW_FIELD(2, water_before)
GROW_FIELD(3, growth)

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  float qc = water[id], g = growth[id];
  growth[id] = g + ((qc - water_before[id]) / P.grid.y - g) * P.sources.z;
  water_before[id] = qc;
}
