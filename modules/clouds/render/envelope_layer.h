#pragma once
// The Envelope method's orographic clouds on the GPU (issue 24; the 2023 talk's "Envelope Method", seed 000): the
// baked 2D maps (modules/clouds/envelope/envelope_maps.h) as textures, and the march (shaders/clouds/envelope_march.comp,
// cone + distance step mapping, or fixed steps) into a colour and depth layer that the clouds' composite orders
// against the voxel clouds and the 2.5D sky by depth.
//
//   EnvelopeLayer env(ctx, library, prepare_sky_noise());
//   env.set_maps(maps);                                    // when the bake changes
//   EnvelopeLayer::Outputs o = env.add_passes(graph, draw, march, cloud_inputs, scene_depth);
//   cloud_inputs.envelope_color = o.color; cloud_inputs.envelope_depth = o.depth;
//
// Resolution: the talk "did away with temporal upscaling and split the render into two passes: lower resolution near
// camera ..., and higher farther away". With `split_m` > 0 the stretch of each ray before it is marched at half the
// layer's resolution and the rest at the layer's, and the composite merges the two; with 0 one pass.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/graph/render_graph.h"
#include "engine/render/render_feature.h"
#include "modules/clouds/envelope/envelope_maps.h"
#include "modules/clouds/envelope/envelope_query.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/render/terrain_heightfield.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::gpu {
class Context;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

// What the level and the weather set for this frame (frame/cloud_frame.h EnvelopeFrame turned into render terms).
struct EnvelopeDraw {
  std::shared_ptr<const envelope::EnvelopeMaps> maps;
  float density = 1.0f;   // x the density (the component's, times the weather's)
  float coverage = 1.0f;  // x the maps' coverage
  float edge_m = 35.0f;   // the edge gradient's width (the talk's 35)
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;  // m/s: the noise scrolls (pseudomotion)
};

// How it is marched (cumulo run --envelope-*).
struct EnvelopeMarchSettings {
  bool cone_stepping = true;   // --envelope-stepping cone|fixed
  float step_m = 8.0f;         // the small step inside the envelope, at the camera
  float step_growth = 0.004f;  // ... growing by this many metres per metre of distance
  uint32_t max_steps = 384;
  float light_step_m = 24.0f;  // the first light sample's length (then x2, x4, x8)
  float draw_distance_m = 24000.0f;
  float resolution_scale = 1.0f;  // of the output (times the frame's dynamic scale)
  float split_m = 0.0f;           // > 0: near (half the layer's resolution) and far passes split at this distance
  // The far (or only) pass marches one pixel of each BxB block a frame and reprojects the rest (reconstruct.comp); 1:
  // every pixel, the talk's way ("we did away with temporal upscaling"), the default on a GPU. On a CPU device the
  // envelope marched in full at 320x180 cost 26-39 ms of the mixed view's 60 Hz frame (the voxel clouds' far segment
  // 20 ms at 1 of 16): envelope_block_for_device.
  uint32_t far_block = 1;
  uint32_t near_block = 1;  // the same for the split's near pass (a CPU device: 4, as the voxel clouds' near segment)
  // The up-rez (envelope_query.h documents the constants).
  float noise_tile_m = envelope::kNoiseTileM, detail_tile_m = envelope::kDetailTileM;
  float detail_erosion = envelope::kDetailErosion;  // 0: the talk's up-rez alone
  float density_scale = envelope::kDensityScale;
  // The envelope's shadow on the terrain (envelope_shadow.comp): texels per side of its own map, and of the map it makes
  // with the voxel clouds' (the one the geometry reads); marched every frame, or (false: a CPU device) again only when
  // the light, the draw or the maps changed or the noise scrolled half a texel.
  uint32_t shadow_texels = 512;
  uint32_t combined_shadow_texels = 1024;
  bool shadow_every_frame = true;
};

// The far pass's block on a device: 1 on a GPU; on a CPU device the voxel clouds' own (2 at 30 Hz, 4 for the 40/60 Hz
// far segment).
uint32_t envelope_block_for_device(bool cpu_device, bool split);
// The mean over an RGBA8 detail noise's level 0 of its fBm (R 0.625 + G 0.25 + B 0.125, as envelope_density.glsl
// erodes with), 0 for an empty volume: the slab lighting's light samples erode by it (envelope_march.comp).
float detail_mean_fbm(const Volume& detail);
// Whether any texel column of the envelope (its conservative bottom to top) comes within `distance` of `p`.
bool envelope_within(const envelope::EnvelopeMaps& maps, glm::vec3 p, float distance);
// Whether the box [lo, hi] may be seen through `view_proj` (conservative: false only when all its corners lie beyond
// one of the left, right, bottom, top and near planes); false for an empty box (lo > hi).
bool envelope_in_view(const glm::mat4& view_proj, glm::vec3 lo, glm::vec3 hi);

class EnvelopeLayer {
 public:
  // `noise_dir`: prepare_sky_noise()'s folder (the Nubis noise of the envelope's generation). Throws cumulo::Error for a
  // missing or malformed noise file.
  EnvelopeLayer(gpu::Context& ctx, gpu::PipelineLibrary& library, const std::filesystem::path& noise_dir);
  ~EnvelopeLayer();
  EnvelopeLayer(const EnvelopeLayer&) = delete;
  EnvelopeLayer& operator=(const EnvelopeLayer&) = delete;

  // Uploads the maps (a new bake); the old textures are kept until the frames in flight are done with them.
  void set_maps(std::shared_ptr<const envelope::EnvelopeMaps> maps, uint64_t frame_index);
  bool has_maps() const;
  // The terrain the maps were baked over (its heights): where the envelope's shadow falls. Without it, no shadow.
  void set_terrain(const TerrainHeightfield& terrain);

  // The envelope's shadow on the scene folded into the voxel clouds' map `voxel` (texture invalid: none): the one map
  // the geometry reads (render::LightShadowMap), on a plane under the envelope. `voxel` unchanged without maps or
  // terrain, with shadows off, or a light lower than kShadowMinLightHeight.
  cumulo::render::LightShadowMap add_shadow_passes(cumulo::render::RenderGraph& graph, const EnvelopeDraw& draw,
                                                   const EnvelopeMarchSettings& march, const CloudFrameInputs& in,
                                                   const cumulo::render::LightShadowMap& voxel);
  uint32_t shadow_updates() const;  // times the envelope's own shadow map was marched

  // The clouds as a medium for the path tracer (reference_trace.comp ENVELOPE): this frame's parameter block and the
  // maps and noise imported into `graph`. Invalid without maps.
  CloudFrameInputs::EnvelopeMedium add_medium(cumulo::render::RenderGraph& graph, const EnvelopeDraw& draw,
                                              const EnvelopeMarchSettings& march, const CloudFrameInputs& in);

  struct Outputs {
    cumulo::render::TextureHandle color;       // RGBA16F: rgb radiance, a transmittance
    cumulo::render::TextureHandle depth;       // RGBA32F: x opacity-0.5 distance (1e6: none), y density samples, z the ray's end, w steps
    cumulo::render::TextureHandle near_color;  // the split's near pass (invalid without the split or when merged)
    cumulo::render::TextureHandle near_depth;
    bool below_output_size = false;  // color / depth are smaller than the graph's output (upsample them)
  };
  Outputs add_passes(cumulo::render::RenderGraph& graph, const EnvelopeDraw& draw, const EnvelopeMarchSettings& march,
                     const CloudFrameInputs& in, cumulo::render::TextureHandle scene_depth);

  // The density (with the near detail), profile, height fraction and edge gradient at world points
  // (envelope_probe.comp): for tests; waits for the device.
  std::vector<glm::vec4> probe(const EnvelopeDraw& draw, const EnvelopeMarchSettings& march, const CloudFrameInputs& in,
                               const std::vector<glm::vec3>& points);
  uint64_t gpu_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cumulo::clouds::render
