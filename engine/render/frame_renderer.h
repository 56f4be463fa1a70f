#pragma once
// The engine's frame: builds a render graph per frame from a FrameSnapshot and records it.
//
//   geometry  (graphics) glTF meshes -> hdr (R16G16B16A16F) + depth (D32F, reversed-Z), sun + ambient + fog
//   sky       (graphics) sky gradient + sun disc into hdr where depth is still the cleared far plane
//   tonemap   (graphics) hdr -> output (swapchain image or offscreen RGBA8), ACES fitted
//
// Feature modules (the clouds, the editor) add passes at the stages of render_feature.h through
// add_feature(): before geometry, after sky (scene colour + depth), after tonemap (the output).
// The renderer reads the snapshot only; it never touches the ECS world.
//
//   FrameRenderer r(ctx);
//   r.record_frame(frame.cmd, snapshot, target, frame.slot);   // gpu::FrameRing slot
//   ... submit; once that frame completed:
//   auto timings = r.pass_timings();               // [(pass, ms)] of the last recorded frame (GPU timestamps)
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/gpu/frames.h"
#include "engine/gpu/vk.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/render_feature.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::render {

inline constexpr uint32_t kFramesInFlight = gpu::kFramesInFlight;

// Where the tonemap pass writes: an acquired swapchain image or an offscreen image.
struct RenderTarget {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{0, 0};
  ResourceState initial, final;  // e.g. acquired() -> present(), or undefined() -> shader_read_only()
  std::string name = "output";
};

class FrameRenderer {
 public:
  // shader_root empty: <repo>/shaders (tests point it at a copy to exercise hot reload).
  explicit FrameRenderer(gpu::Context& ctx, const std::filesystem::path& shader_root = {});
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Records the whole frame into `cmd` (begun by the caller). Throws cumulo::Error for an invalid
  // graph or a model that cannot be uploaded.
  void record_frame(VkCommandBuffer cmd, const FrameSnapshot& snapshot, const RenderTarget& target, uint32_t slot);
  // GPU time per pass of the last recorded frame, in execution order; empty until it completed.
  std::vector<std::pair<std::string, double>> pass_timings() const;
  // The newest completed frame's GPU time per pass (frames in flight: the last recorded one is usually not
  // complete yet) and that frame's number (1-based, increasing; 0: none yet). Dynamic resolution reads it.
  std::pair<uint64_t, std::vector<std::pair<std::string, double>>> latest_completed_pass_timings() const;
  // The compiled graph of the last recorded frame.
  const CompiledGraph& last_compiled() const;  // throws before the first frame
  bool has_recorded() const;                     // a frame was recorded (last_compiled() is there)
  // The render graph's cache of compiled shapes (one per budget mode, debug view, effect present...): how many,
  // how often a graph was compiled, its transient memory layouts and the device memory their images and
  // buffers hold.
  struct GraphCache {
    size_t shapes = 0;
    uint32_t compiles = 0;
    uint64_t transient_bytes = 0;
    size_t transient_images = 0;
    size_t seen = 0;  // distinct shapes compiled since the start: more than the cache holds makes it recompile
    size_t layouts = 0;            // transient memory layouts held (shapes of one layout share its objects)
    uint32_t layouts_created = 0;  // since the start: each one allocated device memory (and may have waited)
  };
  GraphCache graph_cache() const;

  // Windowed runs: recompiles changed shader files; a failure logs the error and keeps the old pipeline.
  // Returns true when a pipeline was rebuilt.
  bool reload_shaders();
  // Compiler errors of pipelines whose latest reload failed (empty when every pipeline is current).
  std::string shader_errors() const;

  // Adds a feature: calls its create_gpu() now (with this renderer's pipeline library) and its passes
  // every frame from then on. Not owned: it must outlive the renderer, whose destructor waits for the
  // device and calls destroy_gpu() on every feature.
  void add_feature(RenderFeature& feature);
  void set_exposure(float exposure) { exposure_ = exposure; }
  // Aerial perspective from the atmosphere's froxels (default), or the SceneLighting height fog.
  void set_aerial_perspective_lut(bool lut) { aerial_lut_ = lut; }
  // Large meshes are drawn per chunk at the coarsest level whose error projects within `px` pixels
  // (mesh_lod.h; default 0.25); 0 draws every chunk at full detail.
  void set_lod_error_px(float px);
  gpu::PipelineLibrary& pipeline_library();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<RenderFeature*> features_;
  float exposure_ = 1.0f;
  bool aerial_lut_ = true;
};

}  // namespace cumulo::render
