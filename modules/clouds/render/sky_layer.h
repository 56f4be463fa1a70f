#pragma once
// The weather-driven 2.5D sky beyond and above the voxel cloudscape (issue 10; the 2023 talk's
// "Vertical Profile Method", i.e. the 2015 talk's spherical shell with cloud types and 2D high layers
// and the 2017 talk's weather map). shaders/clouds/sky_layer.comp has the density model and its sources.
//
//   SkyLayer sky(ctx, library, prepare_sky_noise());
//   const SkyLayerFrame& p = cloud_frame.sky;      // defaults, or from the weather (frame/cloud_extraction.h)
//   SkyLayer::Outputs o = sky.add_passes(graph, p, cloud_inputs, scene_depth, voxel);  // voxel: the march's outputs
//   cloud_inputs.sky_color = o.color; cloud_inputs.sky_depth = o.depth;   // composited with the voxel clouds
//
// Added between the voxel clouds' march and their composite (sky_layer_pass.cpp, add_before_composite): where this
// frame's voxel clouds are opaque in front of the whole shell its march keeps the last value (VOXEL_OCCLUSION).
// Passes: clouds.sky_layer (the march, one pixel of each 4x4 block of a half-resolution target per
// frame: 2015's "1 out of 16 pixels for each 4x4 pixel block") and clouds.sky_layer_reconstruct
// (reconstruct.comp: the other 15 reprojected from the last frame's, the history in the graph); the
// composite upsamples it to full resolution and orders it against the voxel clouds by depth.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/graph/render_graph.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::gpu {
class Context;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

// A cloud map for the GPU: RGBA8, R coverage, G precipitation, B type, 0.5 = the state's value; tiles.
struct CloudMapImage {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
  float tile_m = 32000.0f;  // one tile's extent on the ground
};
// Procedural (tiling fBm at the source's seed, octaves and feature scale) or the painted PNG (its tile
// is 4 x scale_km). Throws cumulo::Error naming the PNG for a bad one.
CloudMapImage make_cloud_map(const weather::CloudMapSource& source, uint32_t texels = 256);

class SkyLayer {
 public:
  // `noise_dir`: prepare_sky_noise()'s folder. Throws cumulo::Error for a missing or malformed noise file.
  SkyLayer(gpu::Context& ctx, gpu::PipelineLibrary& library, const std::filesystem::path& noise_dir);
  ~SkyLayer();
  SkyLayer(const SkyLayer&) = delete;
  SkyLayer& operator=(const SkyLayer&) = delete;

  struct Outputs {
    cumulo::render::TextureHandle color;  // half resolution RGBA16F: rgb radiance, a transmittance
    cumulo::render::TextureHandle depth;  // half resolution RGBA32F: x opacity-0.5 distance (1e6: none), y steps
  };
  // The frame's passes (camera, sun, ambient, extinction and phase from `in`; the yield boxes are its
  // instances). Nothing (invalid outputs) when !sky.enabled.
  // `voxel` (optional): this frame's voxel clouds (the march's colour and depth): where they are opaque in front of the
  // whole shell the layer is not marched (its last value is kept, reprojected).
  Outputs add_passes(cumulo::render::RenderGraph& graph, const SkyLayerFrame& sky, const CloudFrameInputs& in,
                     cumulo::render::TextureHandle scene_depth, const CloudPassOutputs& voxel = {});
  uint64_t gpu_bytes() const;
  // The layer's density (full detail) at world points with these parameters (sky_layer_probe.comp):
  // for tests and debugging; waits for the device.
  std::vector<float> probe_density(const SkyLayerFrame& sky, const CloudFrameInputs& in, const std::vector<glm::vec3>& points);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cumulo::clouds::render
