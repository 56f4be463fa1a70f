// The Envelope method's orographic clouds (envelope_layer.h) as a frame pass (cloud_frame_pass.h): the level's
// OrographicClouds baked on the CPU over the terrain the frame draws (again when the component changes), then marched
// after the voxel clouds into a layer the composite orders against them and the 2.5D sky. Drawn with --envelope on,
// or auto in a level with an OrographicClouds component.
#include <chrono>
#include <cstdio>
#include <memory>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "modules/clouds/envelope/envelope_bake.h"
#include "modules/clouds/render/cloud_frame_pass.h"
#include "modules/clouds/render/envelope_layer.h"
#include "modules/clouds/render/terrain_heightfield.h"
#include "modules/clouds/scene/cloudscape_assets.h"

namespace cumulo::clouds::render {
namespace {

// The terrain under the envelope is rasterized at this many texels a side over the maps' square (finer than the
// maps, so a map texel's height is the terrain's, not a neighbour's).
constexpr uint32_t kTerrainTexels = 1024;
// A changed component is baked again after this many frames without a further change (a dragged slider rests).
constexpr int kSettleFrames = 3;

class EnvelopePass final : public CloudFramePass {
 public:
  bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options, const CloudLevelFacts& level) override {
    if (!options.envelope.value_or(level.has_orographic_clouds)) return false;
    layer_ = std::make_unique<EnvelopeLayer>(g.ctx, g.library, prepare_sky_noise());
    cpu_device_ = g.ctx.info().is_cpu();
    options_ = &options;
    return true;
  }
  void destroy_gpu() override {
    layer_.reset();
    maps_.reset();
    bake_key_.clear();
  }

  void add_before_scene(cumulo::render::StageContext& stage, const CloudFrame& frame, const CloudFrameInputs& in,
                        cumulo::render::LightShadowMap& shadow) override {
    if (frame.envelopes.empty()) return;
    const EnvelopeFrame& e = frame.envelopes.front();
    if (!ensure_baked(stage.snapshot, e, in.frame_index)) return;
    shadow = layer_->add_shadow_passes(stage.graph, draw_for(e), march_for(in), in, shadow);
  }

  // The path tracer traces the same clouds (cumulo fidelity, cumulo reference).
  void add_before_reference(cumulo::render::StageContext& stage, const CloudFrame& frame, CloudFrameInputs& in) override {
    if (frame.envelopes.empty()) return;
    const EnvelopeFrame& e = frame.envelopes.front();
    if (!ensure_baked(stage.snapshot, e, in.frame_index)) return;
    in.envelope_medium = layer_->add_medium(stage.graph, draw_for(e), march_for(in), in);
  }

  void add_before_composite(cumulo::render::StageContext& stage, const CloudFrame& frame, const CloudPassOutputs&,
                            CloudFrameInputs& in) override {
    if (frame.envelopes.empty()) return;
    const EnvelopeFrame& e = frame.envelopes.front();
    if (!ensure_baked(stage.snapshot, e, in.frame_index)) return;
    const EnvelopeLayer::Outputs o = layer_->add_passes(stage.graph, draw_for(e), march_for(in), in, stage.depth);
    in.envelope_color = o.color;
    in.envelope_depth = o.depth;
    in.envelope_near_color = o.near_color;
    in.envelope_near_depth = o.near_depth;
    in.envelope_upsample = o.below_output_size;
  }
  cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) override { return c.stage.hdr; }

 private:
  EnvelopeDraw draw_for(const EnvelopeFrame& e) const {
    EnvelopeDraw draw;
    draw.maps = maps_;
    draw.density = e.density;
    draw.coverage = e.coverage;
    draw.edge_m = e.edge_m;
    draw.wind_direction = e.wind_direction;
    draw.wind_speed = e.wind_speed;
    return draw;
  }
  EnvelopeMarchSettings march_for(const CloudFrameInputs& in) const {
    EnvelopeMarchSettings march;
    march.cone_stepping = options_->envelope_cone_stepping;
    march.split_m = in.settings.split ? in.settings.split_distance_m : 0.0f;
    march.far_block = options_->envelope_block > 0 ? options_->envelope_block
                                                   : envelope_block_for_device(cpu_device_, march.split_m > 0.0f);
    march.near_block = cpu_device_ ? 4u : 1u;
    // On a CPU device the layer is marched at half the output's size as well (the bank view's far pass cost 12 ms of a
    // 60 Hz frame at 320x180 marching 1 of 16 pixels at full size); the composite upsamples it depth-aware.
    if (cpu_device_) march.resolution_scale = 0.5f;
    // cumulo fidelity measures the lighting against the path tracer: every pixel marched at the output's size in both
    // passes (the CPU device's half size and 1-of-16 near pass put the bank's smoothed edge over the hill in `ground`).
    if (options_->reference_comparable) {
      march.resolution_scale = 1.0f, march.near_block = 1u;
      if (options_->envelope_block == 0) march.far_block = 1u;  // --envelope-reprojection 4|16 measures the sub-sampling
    }
    // Its shadow on the terrain: marched again only when something changed (or the noise scrolled half a texel).
    if (cpu_device_) march.shadow_texels = 256, march.combined_shadow_texels = 512, march.shadow_every_frame = false;
    return march;
  }

  // The maps of `e`'s component, baked over the snapshot's terrain when its spec changed. A bake that fails the first
  // time stops the run (the error names the file and the place); later (an edit) it keeps the last good maps.
  bool ensure_baked(const cumulo::render::FrameSnapshot& snapshot, const EnvelopeFrame& e, uint64_t frame_index) {
    if (!e.spec) return false;
    if (maps_ && e.bake_key == bake_key_) return true;
    if (failed_key_ == e.bake_key) return bool(maps_);
    // A changed component (the editor's slider) bakes again once it has rested kSettleFrames frames; the last maps draw
    // meanwhile. With no maps yet it bakes at once.
    if (maps_) {
      if (e.bake_key != pending_key_) {
        pending_key_ = e.bake_key;
        pending_frames_ = 0;
      }
      // Called before the scene and again before the composite: one count per frame.
      if (frame_index != pending_frame_) pending_frame_ = frame_index, ++pending_frames_;
      if (pending_frames_ < kSettleFrames) return true;
    }
    try {
      const auto start = std::chrono::steady_clock::now();
      const envelope::OrographicClouds& spec = *e.spec;
      const glm::vec2 lo = spec.extent_min, hi = spec.extent_max;
      const float side = std::max(hi.x - lo.x, hi.y - lo.y);
      const TerrainHeightfield terrain = rasterize_heightfield(snapshot.models, kTerrainTexels, lo, side);
      auto height = [&terrain](float x, float z) { return std::max(terrain.height_at(x, z, 0.0f), 0.0f); };
      auto maps = std::make_shared<envelope::EnvelopeMaps>(envelope::bake_envelope_maps(spec, height));
      maps_ = std::move(maps);
      layer_->set_terrain(terrain);
      bake_key_ = e.bake_key;
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "cumulo: envelope clouds (%s): baked %ux%u maps over the terrain in %.2f s\n",
                   spec.where.c_str(), maps_->resolution, maps_->resolution, s);
      return true;
    } catch (const Error& err) {
      if (!maps_) throw;
      std::fprintf(stderr, "cumulo: the envelope clouds keep their last maps: %s\n", err.what());
      failed_key_ = e.bake_key;
      return true;
    }
  }

  std::unique_ptr<EnvelopeLayer> layer_;
  const CloudRenderOptions* options_ = nullptr;
  bool cpu_device_ = false;
  std::shared_ptr<const envelope::EnvelopeMaps> maps_;
  std::string bake_key_, failed_key_, pending_key_;
  int pending_frames_ = 0;
  uint64_t pending_frame_ = ~0ull;
};

}  // namespace

std::unique_ptr<CloudFramePass> make_envelope_pass() { return std::make_unique<EnvelopePass>(); }

}  // namespace cumulo::clouds::render
