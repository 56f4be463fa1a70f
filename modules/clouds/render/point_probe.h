#pragma once
// A density probe's dispatch (the 2.5D sky's and the envelope's `probe`, for tests and debugging): the world points
// uploaded as vec4 (w = 1), a compute pipeline run once per point with uvec4(count) as push constants, and `stride`
// bytes per point read back. `bind` adds the pipeline's own bindings (its parameter block, its textures) to the writer,
// whose point and result buffers are at `points_binding` and `out_binding`. Waits for the device.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::gpu {
class Context;
class DescriptorWriter;
class Pipeline;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

std::vector<uint8_t> run_point_probe(gpu::Context& ctx, gpu::Pipeline& pipe, const std::vector<glm::vec3>& points,
                                     uint32_t stride, uint32_t points_binding, uint32_t out_binding,
                                     const std::function<void(gpu::DescriptorWriter&)>& bind);

}  // namespace cumulo::clouds::render
