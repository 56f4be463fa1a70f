#include "modules/clouds/render/point_probe.h"

#include <cstring>

#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"

namespace cumulo::clouds::render {

std::vector<uint8_t> run_point_probe(gpu::Context& ctx, gpu::Pipeline& pipe, const std::vector<glm::vec3>& points,
                                     uint32_t stride, uint32_t points_binding, uint32_t out_binding,
                                     const std::function<void(gpu::DescriptorWriter&)>& bind) {
  const uint32_t n = uint32_t(points.size());
  if (n == 0) return {};
  gpu::Buffer in_buf(ctx, {n * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                           "probe points"});
  std::vector<glm::vec4> pts(n);
  for (uint32_t i = 0; i < n; ++i) pts[i] = glm::vec4(points[i], 1.0f);
  std::memcpy(in_buf.mapped(), pts.data(), n * sizeof(glm::vec4));
  gpu::Buffer out_buf(ctx, {VkDeviceSize(n) * stride, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Readback,
                            "probe out"});
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    pipe.bind(cmd);
    gpu::DescriptorWriter w;
    bind(w);
    w.storage_buffer(points_binding, in_buf.handle()).storage_buffer(out_binding, out_buf.handle()).push(ctx, cmd, pipe);
    const glm::uvec4 count(n, 0, 0, 0);
    pipe.push_constants(cmd, count);
    pipe.dispatch_threads(cmd, n, 1, 1);
    gpu::cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                            VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::vector<uint8_t> out(size_t(n) * stride);
  out_buf.download(out.data(), out.size());
  return out;
}

}  // namespace cumulo::clouds::render
