#pragma once
// Per-frame command buffers and fences: kFramesInFlight (2) slots used round-robin, so the CPU
// records frame N+1 while the GPU runs frame N.
//
//   gpu::FrameRing frames(ctx);
//   gpu::Frame& f = frames.begin();        // waits for this slot's previous frame, begins f.cmd
//   timer.begin_frame(f.slot);             // slot results are complete now
//   auto image = swapchain.acquire(f.acquired);                      // windowed
//   ... record into f.cmd ...
//   frames.submit(f, f.acquired, swapchain.render_finished(*image));  // or frames.submit(f) headless
//   swapchain.present(*image);
#include <cstdint>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

constexpr uint32_t kFramesInFlight = 2;

struct Frame {
  uint32_t slot = 0;    // 0 .. frames-1: index per-frame resources with it
  uint64_t number = 0;  // frames begun so far, this one included
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;         // signalled when this slot's submission completes
  VkSemaphore acquired = VK_NULL_HANDLE;  // for swapchain acquire: signalled by the presentation engine
  VkCommandPool pool = VK_NULL_HANDLE;
  bool submitted = false;
};

class FrameRing {
 public:
  explicit FrameRing(Context& ctx, uint32_t frames = kFramesInFlight);
  ~FrameRing();
  FrameRing(const FrameRing&) = delete;
  FrameRing& operator=(const FrameRing&) = delete;

  Frame& begin();
  // Ends f.cmd and submits it with f.fence. `wait` (e.g. f.acquired) is waited at `wait_stage`;
  // `signal` (e.g. swapchain.render_finished(index)) is signalled at the end.
  void submit(Frame& f, VkSemaphore wait = VK_NULL_HANDLE, VkSemaphore signal = VK_NULL_HANDLE,
              VkPipelineStageFlags2 wait_stage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                 VK_PIPELINE_STAGE_2_TRANSFER_BIT |
                                                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  void wait_all();  // waits for every submitted frame
  uint32_t size() const { return uint32_t(frames_.size()); }
  uint64_t frame_number() const { return number_; }

 private:
  Context& ctx_;
  std::vector<Frame> frames_;
  uint64_t number_ = 0;
};

}  // namespace cumulo::gpu
