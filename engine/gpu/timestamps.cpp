#include "engine/gpu/timestamps.h"

#include "engine/core/error.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

GpuTimer::GpuTimer(Context& ctx, uint32_t frame_slots, uint32_t max_ranges)
    : ctx_(ctx), max_ranges_(max_ranges), slots_(frame_slots) {
  supported_ = ctx.info().timestamps;
  if (!supported_) return;
  period_ns_ = ctx.info().limits.timestampPeriod;
  uint32_t qn = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device(), &qn, nullptr);
  std::vector<VkQueueFamilyProperties> qf(qn);
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device(), &qn, qf.data());
  uint32_t bits = qf[ctx.queue_family()].timestampValidBits;
  valid_mask_ = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = frame_slots * max_ranges * 2;
  VK_CHECK(vkCreateQueryPool(ctx.device(), &info, nullptr, &pool_));
  ctx.set_name(pool_, "gpu timer");
  vkResetQueryPool(ctx.device(), pool_, 0, info.queryCount);
  for (auto& s : slots_) s.reset = true;
}

GpuTimer::~GpuTimer() {
  if (pool_) vkDestroyQueryPool(ctx_.device(), pool_, nullptr);
}

const std::vector<TimedRange>& GpuTimer::begin_frame(uint32_t slot) {
  if (slot >= slots_.size()) fail("GpuTimer: slot %u of %zu", slot, slots_.size());
  last_ = collect(slot);
  current_ = slot;
  if (supported_) {
    Slot& s = slots_[slot];
    if (!s.reset) vkResetQueryPool(ctx_.device(), pool_, slot * max_ranges_ * 2, max_ranges_ * 2);
    s.reset = true;
    s.names.clear();
    s.ended.clear();
  }
  return last_;
}

uint32_t GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
  Slot& s = slots_[current_];
  if (!supported_ || s.names.size() >= max_ranges_) return UINT32_MAX;
  uint32_t r = uint32_t(s.names.size());
  s.names.push_back(name);
  s.ended.push_back(false);
  s.reset = false;
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, (current_ * max_ranges_ + r) * 2);
  return r;
}

void GpuTimer::end(VkCommandBuffer cmd, uint32_t r) {
  Slot& s = slots_[current_];
  if (r == UINT32_MAX || r >= s.names.size() || s.ended[r]) return;
  s.ended[r] = true;
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, (current_ * max_ranges_ + r) * 2 + 1);
}

std::vector<TimedRange> GpuTimer::collect(uint32_t slot) {
  std::vector<TimedRange> out;
  if (!supported_ || slot >= slots_.size()) return out;
  Slot& s = slots_[slot];
  if (s.names.empty()) return out;
  for (size_t r = 0; r < s.names.size(); ++r) {
    if (!s.ended[r]) continue;  // never query an unwritten timestamp: WAIT would block forever
    uint64_t t[2];
    // WAIT: callers only collect after the slot's fence, so this returns at once.
    VK_CHECK(vkGetQueryPoolResults(ctx_.device(), pool_, uint32_t((slot * max_ranges_ + r) * 2), 2, sizeof t, t, 8,
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    uint64_t dt = ((t[1] & valid_mask_) - (t[0] & valid_mask_)) & valid_mask_;
    out.push_back({s.names[r], double(dt) * period_ns_ * 1e-6});
  }
  return out;
}

}  // namespace cumulo::gpu
