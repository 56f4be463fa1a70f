#pragma once
// GpuGrownAsset: the march's inputs made on the GPU from the cloud-formation solver's current state (issue 26,
// "clouds that grow while you watch"): the modeling image (RGBA8: r profile, g detail type, b density scale,
// a coverage threshold) and the field image (R16 unorm 0..1 <-> -256..4096 m, rounded down), as the offline path
// makes them from a grown cloud (grow/grown_attributes.h's derive_modeling, then the bake's encoding, bake.cpp and
// field.h), refreshed by record_update after any step. Shaders: shaders/clouds/grow/sdf_*.comp and attr_*.comp.
//
//   grow_gpu::GpuCloudSolver solver(ctx, library, spec.solver);
//   grow_gpu::GpuGrownAsset grown(ctx, library, spec.solver.dims, grow_gpu::grown_asset_settings(spec));
//   ctx.submit_and_wait([&](VkCommandBuffer cmd) { solver.record_step(cmd); grown.record_update(cmd, solver); });
//   grow_gpu::GrownAssetView v = grown.view();   // the images, dims, voxel size and box the march binds
//
// Index:  GrownAssetSettings  grown_asset_settings  GrownAssetGrid  grown_asset_grid  GrownAssetView  GpuGrownAsset
//
// The grid (derive_modeling's): f = ceil(cell / voxel size) voxels per solver cell, voxel = cell / f game metres,
// (cells - 1) f + 1 voxels per axis, voxel i at cell i / f; over the WHOLE solver box (no crop: the box does not
// move while the cloud grows). The local frame (game metres): GrownAssetSettings::origin is where the solver's cell
// (0, 0, 0) centre lies; by default x and z centred on the box and y = 0 at its floor. (grow_cloud's frame, x/z
// centred on the cloud and y = 0 at its base, moves as the cloud grows: pass that origin to place a cloud where its
// offline bake sits.)
//
// Per update (all compute, one barrier between dependent passes; no float atomics, the same state gives the same
// bytes):
//  - the distance: the cloud water resampled (trilinear) at the voxels and thresholded at the iso; jump flooding
//    (log2 N passes and three more of steps 4, 2, 1) finds each voxel's nearest voxel of the other class; the
//    distance between their centres less half a voxel, and next to the surface the sub-voxel iso-crossing, as
//    derive_modeling (the profile and its depth read this distance);
//  - the field image: that distance made conservative (a 3x3x3 pass d(v) <= d(n) + |v - n|, then less the safety
//    margin, 1 % of a positive distance), clamped to the field's range and rounded down as field_to_unorm16;
//  - the attributes by derive_modeling's rules on the solver's cells: the percentiles exact (a radix select over
//    the values' bits with integer-atomic histograms), the column heights, the rates, four rings of dilation, the
//    detail type's blur; the profile depth from the distance (max filter, thickness factor, clamp); the profile
//    (profile_from_field with the recipe defaults a grown edit gets: its own depth, exponent 1) and the bake's
//    rounding.
// Not made on the GPU: grow_cloud's speckle removal (its percentiles count every cell above the iso), the
// fair-weather field (view().field_fair is one texel of -256 m, as a bake without one), BC1.
// tests/modules/clouds/grow_gpu/grown_asset_gpu_test.cpp states how close and how conservative, and the cost.
//
// Layering: this folder uses no header of modules/clouds/render (the renderer, which will step the solver, is to
// include this one; scripts/check_layering.py refuses a cycle): GrownAssetView carries what a render::CloudAsset
// holds, borrowed.
#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/vk.h"
#include "shared/grown_asset_params.h"

namespace cumulo::gpu {
class Context;
class GpuTimer;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu
namespace cumulo::clouds::grow {
struct GrowSpec;
}

namespace cumulo::clouds::grow_gpu {

class GpuCloudSolver;

struct GrownAssetSettings {
  float cell_game = 16.0f;     // game metres per solver cell (GrowSpec::cell_game; physical = game x the spec's scale)
  float iso = 0.05e-3f;        // kg/kg: the cloud's surface (GrowSpec::iso)
  float voxel_size = 8.0f;     // the largest output voxel, game metres (derive_modeling's 8)
  bool default_origin = true;  // origin: x/z centred on the solver's box, y = 0 at its floor
  glm::vec3 origin{0.0f};      // else: the local position of the solver's cell (0, 0, 0) centre, game metres
  float coverage = 0.0f;       // the modeling alpha (a grown edit's coverage threshold: the recipe default 0)
  float profile_exponent = 1.0f;  // the recipe's profile exponent (default 1)
  // Jump flooding's passes after the log2 N halving ones: steps 2^(k-1) .. 1 (3: 4, 2, 1). With 2 (the usual
  // JFA+2), a 6 m grid of the tests kept a farther seed for 66 voxels 280-320 m from the cloud (up to 2.4 m, 0.8 %
  // of the distance); with 3, none in any test grid.
  int flood_extra_passes = 3;
  // Taken off the stored (positive) distance: safety_fraction of it plus safety_margin metres. Jump flooding's
  // errors grow with the distance (thin Voronoi cells far from the surface); 1 % covers the weaker flood's worst
  // (0.6 % after the 3x3x3 pass) with room, and costs the march 1 % shorter steps through empty space.
  float safety_fraction = 0.01f;
  float safety_margin = 0.0f;
};
GrownAssetSettings grown_asset_settings(const grow::GrowSpec& spec, float voxel_size = 8.0f);

// The output grid over the solver's box.
struct GrownAssetGrid {
  glm::ivec3 cells{0};     // the solver's
  int per_cell = 1;        // f: voxels per cell
  float voxel = 8.0f;      // game metres
  glm::ivec3 voxels{0};    // (cells - 1) f + 1
  glm::vec3 origin{0.0f};  // local position of voxel (0, 0, 0)'s centre (= the solver's cell (0, 0, 0) centre)
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // the voxels' box (origin - voxel / 2 .. last centre + voxel / 2)
  size_t count() const { return size_t(voxels.x) * voxels.y * voxels.z; }
  size_t index(int x, int y, int z) const { return size_t(x) + size_t(voxels.x) * (size_t(y) + size_t(voxels.y) * z); }
};
GrownAssetGrid grown_asset_grid(glm::ivec3 cells, const GrownAssetSettings& s);

// What the renderer binds for a grown cloud: a render::CloudAsset's images and box in its uncompressed formats
// (modeling RGBA8 with the coverage alpha, field R16 unorm), no fair-weather field (field_fair is one texel of
// -256 m, which the march reads as "inside" and so falls back to the field, as cloud_assets.cpp does for a bake
// without one). Borrowed: the images live as long as the GpuGrownAsset, in SHADER_READ_ONLY_OPTIMAL between updates.
struct GrownAssetView {
  const gpu::Image* modeling = nullptr;
  const gpu::Image* field = nullptr;
  const gpu::Image* field_fair = nullptr;
  glm::uvec3 dims{0};
  float voxel_size = 0.0f;                       // game metres
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // the local frame's box (game metres)
  uint64_t gpu_bytes = 0;                        // texel bytes of the modeling and the field
};

// How record_update orders its passes: the attributes' passes beside the distance's (fewer barrier intervals; the
// timer ranges grown.classify, grown.flood, grown.distance, grown.store), or the distance field whole and then the
// attributes (ranges grown.sdf and grown.attributes: what `cumulo bench` reports apart); in both the two images are
// written last (range grown.images: the field's conservative pass and the modeling store). Same bytes.
enum class GrownUpdateOrder { Interleaved, Apart };

// A run of an update's stages (barrier intervals) that one frame records: [first, first + count).
struct GrownUpdateChunk {
  int first = 0, count = 0;
};

class GpuGrownAsset {
 public:
  // `cells`: the solver's grid (GpuCloudSolver::dims()). Creates the images (cleared to "no cloud": the field's
  // maximum, modeling 0) and the scratch buffers.
  GpuGrownAsset(gpu::Context& ctx, gpu::PipelineLibrary& library, glm::ivec3 cells, const GrownAssetSettings& settings);
  ~GpuGrownAsset();
  GpuGrownAsset(const GpuGrownAsset&) = delete;
  GpuGrownAsset& operator=(const GpuGrownAsset&) = delete;

  // Records the recomputation of both images from the solver's current buffers (after the steps recorded before
  // it). Starts with a barrier; the images end in SHADER_READ_ONLY_OPTIMAL, visible to later commands. With a
  // timer: one range per stage (GrownUpdateOrder says which).
  void record_update(VkCommandBuffer cmd, const GpuCloudSolver& solver, gpu::GpuTimer* timer = nullptr,
                     GrownUpdateOrder order = GrownUpdateOrder::Interleaved);
  // The same update spread over frames: the stages [first, first + count) of the interleaved order (or the order
  // given), recorded in one command buffer; the runs of one update in later command buffers in turn, with no step of
  // the solver between the first and the last (the attributes read its buffers in several stages). Only the last stage
  // writes the images, so they show the previous update until then. Bytes: the same as record_update's.
  void record_update_stages(VkCommandBuffer cmd, const GpuCloudSolver& solver, int first, int count,
                            gpu::GpuTimer* timer = nullptr, GrownUpdateOrder order = GrownUpdateOrder::Interleaved);
  // The interleaved update cut into `frames` runs (fewer if it has fewer stages): the last stage, the images, alone
  // in the last run (its frame rebuilds the light grid), the stages before it in runs of about equal estimated cost
  // (work groups x the texels a thread reads). frames = 1: one run of every stage.
  std::vector<GrownUpdateChunk> update_chunks(const GpuCloudSolver& solver, int frames) const;
  int updates_recorded() const { return updates_; }  // whole updates (their last stage recorded)
  int stages_recorded() const { return stages_recorded_; }
  // Records a copy of the modeling image (RGBA8, x fastest) into `dst` (a host-readable buffer of
  // grid().count() x 4 bytes), visible to the host once the submission completes; after an update.
  void record_modeling_copy(VkCommandBuffer cmd, VkBuffer dst) const;

  // The images as the march binds them. Their contents change with each update: frames in flight must be done
  // with them first.
  GrownAssetView view() const;
  const GrownAssetGrid& grid() const { return grid_; }
  const GrownAssetSettings& settings() const { return s_; }

  // Read-backs for checks (wait; call once the recorded update completed).
  std::vector<uint8_t> read_modeling() const;   // RGBA8 per voxel, x fastest
  std::vector<uint16_t> read_field() const;     // R16 per voxel
  std::vector<float> read_cloud_water() const;  // the cloud water resampled at the voxels (what was thresholded)
  std::vector<float> read_distance() const;     // metres: the modeling's distance, before the conservative pass
  std::array<float, GROWN_QUANTITIES> read_percentiles() const;  // |condensation|, |w|, |growth| 90th; qc median

 private:
  struct Pipes {
    const gpu::Pipeline *resample, *jfa, *distance, *store_field;
    const gpu::Pipeline *histogram, *select, *column, *rates, *dilate, *blur, *depth, *store_modeling;
  };
  // A barrier interval of the update: its passes, their estimated cost, the timer range that starts with it.
  struct Stage {
    float cost = 0.0f;
    const char* range = nullptr;
    std::vector<std::function<void(VkCommandBuffer)>> passes;
  };
  // The stages for `solver`'s buffers, built once per solver and order (an update spread over frames records a run
  // of them every frame).
  const std::vector<Stage>& stages(const GpuCloudSolver& solver, GrownUpdateOrder order) const;
  std::vector<Stage> build_stages(const GpuCloudSolver& solver, GrownUpdateOrder order) const;
  void pass(VkCommandBuffer cmd, const gpu::Pipeline& pipe, const std::vector<VkBuffer>& buffers, uint32_t groups,
            int pass_x = 0, int axis = 0, int radix = 0) const;
  uint32_t voxel_groups() const;
  uint32_t cell_groups() const;
  void clear_images();

  gpu::Context& ctx_;
  GrownAssetSettings s_;
  GrownAssetGrid grid_;
  Pipes pipes_{};
  mutable gpu::Image modeling_, field_;  // mutable: a read-back tracks their layout
  gpu::Image field_fair_;
  gpu::Buffer params_;
  gpu::Buffer fine_, seeds_a_, seeds_b_, distance_;  // per voxel; the depth passes reuse the two seed buffers
  gpu::Buffer select_, columns_, attributes_a_, attributes_b_;  // the percentiles' state, per column, per cell
  std::vector<int> jfa_steps_;
  int updates_ = 0;
  int stages_recorded_ = 0;
  struct StageCache {
    std::array<VkBuffer, 4> solver{};  // the solver buffers they read (cloud water, condensation, growth, v)
    std::vector<Stage> list;
  };
  mutable std::array<StageCache, 2> stage_cache_;  // by GrownUpdateOrder
};

}  // namespace cumulo::clouds::grow_gpu
