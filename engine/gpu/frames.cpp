#include "engine/gpu/frames.h"

#include "engine/core/error.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

FrameRing::FrameRing(Context& ctx, uint32_t count) : ctx_(ctx), frames_(count) {
  for (uint32_t i = 0; i < count; ++i) {
    Frame& f = frames_[i];
    f.slot = i;
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    pi.queueFamilyIndex = ctx.queue_family();
    VK_CHECK(vkCreateCommandPool(ctx.device(), &pi, nullptr, &f.pool));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = f.pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(ctx.device(), &ai, &f.cmd));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_CHECK(vkCreateFence(ctx.device(), &fi, nullptr, &f.fence));
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(ctx.device(), &si, nullptr, &f.acquired));
    std::string n = "frame " + std::to_string(i);
    ctx.set_name(f.cmd, n);
    ctx.set_name(f.fence, n);
    ctx.set_name(f.acquired, n + " acquired");
  }
}

FrameRing::~FrameRing() {
  wait_all();
  for (Frame& f : frames_) {
    vkDestroySemaphore(ctx_.device(), f.acquired, nullptr);
    vkDestroyFence(ctx_.device(), f.fence, nullptr);
    vkDestroyCommandPool(ctx_.device(), f.pool, nullptr);
  }
}

Frame& FrameRing::begin() {
  Frame& f = frames_[number_ % frames_.size()];
  ++number_;
  if (f.submitted) {
    VK_CHECK(vkWaitForFences(ctx_.device(), 1, &f.fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(ctx_.device(), 1, &f.fence));
    f.submitted = false;
  }
  f.number = number_;
  VK_CHECK(vkResetCommandPool(ctx_.device(), f.pool, 0));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(f.cmd, &bi));
  return f;
}

void FrameRing::submit(Frame& f, VkSemaphore wait, VkSemaphore signal, VkPipelineStageFlags2 wait_stage) {
  VK_CHECK(vkEndCommandBuffer(f.cmd));
  VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cbi.commandBuffer = f.cmd;
  VkSemaphoreSubmitInfo wi{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  wi.semaphore = wait;
  wi.stageMask = wait_stage;
  VkSemaphoreSubmitInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  si.semaphore = signal;
  si.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  VkSubmitInfo2 info{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  info.waitSemaphoreInfoCount = wait ? 1 : 0;
  info.pWaitSemaphoreInfos = &wi;
  info.signalSemaphoreInfoCount = signal ? 1 : 0;
  info.pSignalSemaphoreInfos = &si;
  info.commandBufferInfoCount = 1;
  info.pCommandBufferInfos = &cbi;
  ctx_.submit(info, f.fence);
  f.submitted = true;
}

void FrameRing::wait_all() {
  for (Frame& f : frames_) {
    if (!f.submitted) continue;
    vkWaitForFences(ctx_.device(), 1, &f.fence, VK_TRUE, UINT64_MAX);
    vkResetFences(ctx_.device(), 1, &f.fence);
    f.submitted = false;
  }
}

}  // namespace cumulo::gpu
