#version 450
// The march's inputs from the solver's state, step 1 (grown_attributes.cpp's derive_modeling): the cloud water
// resampled (trilinear) at the output voxels, and each voxel's class (above the iso: inside) with no seed yet, for
// the jump flooding that follows (sdf_jfa.comp).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Water { float water[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Fine { float fine[]; };
layout(set = 0, binding = 3, std430) writeonly buffer Seeds { uint seeds[]; };

GROWN_TRILINEAR(sample_water, water, )

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  float q = sample_water(P.cells.xyz, grown_cell_position(grown_coords(id, P.voxels.xyz)));
  fine[id] = q;
  seeds[id] = (q > P.grid.z ? GROWN_SEED_INSIDE : 0u) | GROWN_SEED_NONE;
}
