#pragma once
// Counts the frames whose scene colour holds a NaN or an infinity, on the GPU (a reduction per frame into four
// counters in host-visible memory, read when asked: no frame is read back). Added last to a renderer, it sees the
// scene colour after every feature's AfterOpaque passes (the clouds composited). `cumulo soak` uses it.
//
//   render::NonFiniteProbe probe;
//   renderer.add_feature(probe);          // after the modules' features
//   ... frames ...; after a frame completed:
//   render::NonFiniteProbe::Counts c = probe.counts();   // frames probed, frames with non-finite texels, texels
#include <cstdint>

#include <glm/vec2.hpp>

#include "engine/gpu/buffer.h"
#include "engine/render/render_feature.h"

namespace cumulo::gpu {
class Pipeline;
}

namespace cumulo::render {

class NonFiniteProbe : public RenderFeature {
 public:
  struct Counts {
    uint64_t frames = 0, bad_frames = 0, bad_pixels = 0;
    glm::ivec2 last_bad_pixel{-1, -1};  // the last bad frame's first non-finite texel (row-major), -1 if none yet
  };
  void create_gpu(GpuServices& g) override;
  void destroy_gpu() override;
  void add_passes(Stage stage, StageContext& f) override;
  // Since create_gpu, up to the last completed frame (call after the frame's fence; host-coherent memory).
  Counts counts() const;

 private:
  gpu::Context* ctx_ = nullptr;
  gpu::Pipeline *count_ = nullptr, *fold_ = nullptr;
  gpu::Buffer counters_;
};

}  // namespace cumulo::render
