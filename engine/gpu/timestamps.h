#pragma once
// GPU timestamps: named ranges per frame slot, read back in milliseconds once the slot's fence has
// signalled. The render graph brackets every pass with begin()/end().
//
//   gpu::GpuTimer timer(ctx, /*frame_slots=*/2);
//   // frame start, after waiting the slot's fence:
//   timer.begin_frame(slot);                 // collects that slot's previous results, resets its queries
//   uint32_t r = timer.begin(cmd, "clouds"); ...; timer.end(cmd, r);
//   for (auto& t : timer.last_results()) printf("%s %.3f ms\n", t.name.c_str(), t.ms);
//
// One-off use: timer.begin_frame(0); ctx.submit_and_wait(record with begin/end); timer.collect(0).
// Queries are reset from the host (hostQueryReset), so no reset command is recorded.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

struct TimedRange {
  std::string name;
  double ms = 0.0;
};

class GpuTimer {
 public:
  GpuTimer(Context& ctx, uint32_t frame_slots = 2, uint32_t max_ranges_per_frame = 128);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // Call once the slot's previous submission is complete. Returns (and keeps as last_results()) the
  // ranges that slot recorded last time, then resets it for new ranges.
  const std::vector<TimedRange>& begin_frame(uint32_t slot);
  // Records a start timestamp; returns the range id for end(). Beyond capacity returns UINT32_MAX (ignored).
  uint32_t begin(VkCommandBuffer cmd, const std::string& name);
  void end(VkCommandBuffer cmd, uint32_t range);
  // Reads `slot`'s ranges (waits for availability). Ranges whose end was never recorded are skipped.
  std::vector<TimedRange> collect(uint32_t slot);
  const std::vector<TimedRange>& last_results() const { return last_; }
  bool supported() const { return supported_; }

 private:
  struct Slot {
    std::vector<std::string> names;
    std::vector<bool> ended;
    bool reset = false;
  };
  Context& ctx_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t max_ranges_;
  uint32_t current_ = 0;
  std::vector<Slot> slots_;
  std::vector<TimedRange> last_;
  bool supported_ = false;
  double period_ns_ = 1.0;
  uint64_t valid_mask_ = ~0ull;
};

}  // namespace cumulo::gpu
