// Parameters of the march's inputs made from the cloud-formation solver's state on the GPU
// (modules/clouds/grow_gpu/grown_asset_gpu.h, issue 26), shared by C++ and GLSL. The passes mirror the offline
// derivation, modules/clouds/bake/grow/grown_attributes.cpp (derive_modeling), and the bake's encoding
// (modules/clouds/bake/field.h, bake.cpp); the names below are theirs.
//
// Two grids: the solver's cells (`cells`, the attributes' rates, percentiles, dilation and blur) and the output
// voxels (`voxels`, node-aligned with the cells: voxel i sits at cell i / f, as derive_modeling's fine grid).
#ifndef CUMULO_SHARED_GROWN_ASSET_PARAMS_H
#define CUMULO_SHARED_GROWN_ASSET_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

#define GROWN_BINDING_PARAMS 0         // uniform GrownAssetParams; each pass's buffers follow from binding 1
#define GROWN_BINDING_FIELD_IMAGE 8    // r16 storage image: the field (sdf_store.comp)
#define GROWN_BINDING_MODELING_IMAGE 9 // rgba8 storage image: the modeling attributes (attr_store.comp)
#define GROWN_LOCAL_SIZE 64            // threads per group of the per-voxel and per-cell passes (1D)
#define GROWN_HISTOGRAM_SIZE 256       // threads per group of attr_histogram.comp
#define GROWN_HISTOGRAM_CELLS 4096     // cells one histogram group counts
#define GROWN_BINS 256                 // one radix digit (8 bits) of a float's bits per select pass
#define GROWN_QUANTITIES 4             // percentiles: |condensation|, |w|, |growth| (90th), cloud water (median)

// A voxel's jump-flooding seed (sdf_jfa.comp): the nearest voxel of the other class found so far, packed
// x | y << 10 | z << 20, with the voxel's own class (cloud water above the iso) in the top bit.
#define GROWN_SEED_NONE 0x3FFFFFFFu
#define GROWN_SEED_MASK 0x3FFFFFFFu
#define GROWN_SEED_INSIDE 0x80000000u
#define GROWN_MAX_VOXELS_PER_AXIS 1023  // so that GROWN_SEED_NONE is no voxel

// The select state (attr_select.comp), per quantity: 4 uints, then the histograms (GROWN_QUANTITIES x GROWN_BINS).
#define GROWN_SELECT_PREFIX 0  // the bits of the k-th value found so far
#define GROWN_SELECT_RANK 1    // k, within the values that share the prefix
#define GROWN_SELECT_COUNT 2   // how many values (cloud cells)
#define GROWN_SELECT_STRIDE 4
#define GROWN_SELECT_HEADER (GROWN_QUANTITIES * GROWN_SELECT_STRIDE)

struct GrownAssetParams {
  ivec4 cells;      // xyz: the solver's cells per axis; w: cells
  ivec4 voxels;     // xyz: output voxels per axis ((cells - 1) f + 1); w: voxels
  vec4 grid;        // x: f, output voxels per cell (a float); y: voxel size (game m); z: iso (kg/kg); w: half a voxel (m)
  vec4 field;       // x: field min (m, 0 in R16); y: field max (m, 1, also the distance with no seed); z: the safety
                    // margin's fraction of a positive distance; w: its metres
  vec4 profile;     // x: thickness factor; y: min profile depth (m); z: max profile depth (m); w: the profile's exponent
  vec4 detail;      // x: growth weight; y: condensation weight; z: updraft weight; w: height weight
  vec4 quantiles;   // per quantity (GROWN_QUANTITIES): the percentile taken (0.9, 0.9, 0.9, 0.5)
  vec4 floors;      // per quantity: the least reference value (grown_attributes.cpp's max(percentile, floor))
  ivec4 radii;      // x: the thickness radius (voxels, the profile depth's max filter); yzw: unused
  vec4 coverage;    // x: the modeling alpha (a coverage threshold, 0..1); yzw: unused
};
CUMULO_SHARED_SIZE(GrownAssetParams, 160)

// Push constants of every pass (each reads what it needs).
struct GrownAssetPush {
  ivec4 pass;  // x: the jump-flooding step (voxels); y: the axis of a separable pass; z: the radix pass (0..3); w: unused
};
CUMULO_SHARED_SIZE(GrownAssetPush, 16)

CUMULO_SHARED_END

#endif
