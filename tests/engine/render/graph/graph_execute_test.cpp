// The render graph executed on Vulkan (lavapipe on CI) with validation + synchronization validation:
// fill (compute) -> blur (compute, sampled read) -> composite (compute, + an imported texture) ->
// readback (copy into an imported host buffer), plus a pass nobody consumes. Checked numerically.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/sampler.h"
#include "engine/gpu/shader_compiler.h"
#include "engine/render/graph/executor.h"
#include "engine/render/graph/render_graph.h"
#include "engine/render/history.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

// True when the loader sees at least one physical device; the test skips only when there is none.
bool any_vulkan_device() {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  VkInstance instance;
  if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return false;
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  vkDestroyInstance(instance, nullptr);
  return count > 0;
}

// The test's own shaders (tests/engine/render/graph/shaders), compiled at run time; layouts come
// from reflection, set 0 is a push-descriptor set (written per dispatch/draw, so frames recorded
// before any completes never share a descriptor set).
gpu::ShaderCompiler test_shaders(const gpu::Context& ctx) {
  return gpu::ShaderCompiler(repo_root() / "tests/engine/render/graph/shaders", ctx.cache_dir() / "shaders");
}

// Binds `p`, pushes its set 0 and runs one thread per texel of `size`.
void dispatch(const gpu::Context& ctx, VkCommandBuffer cmd, const gpu::Pipeline& p, const gpu::DescriptorWriter& set0,
              VkExtent3D size) {
  p.bind(cmd);
  set0.push(ctx, cmd, p);
  p.dispatch_threads(cmd, size.width, size.height);
}

// A fullscreen triangle into `target` (COLOR_ATTACHMENT_OPTIMAL, placed by the graph) sampling `source`.
void draw_fullscreen(const gpu::Context& ctx, VkCommandBuffer cmd, const gpu::Pipeline& p, VkImageView source,
                     VkSampler sampler, VkImageView target, VkExtent3D size) {
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = target;
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is written
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {size.width, size.height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = 1;
  ri.pColorAttachments = &color;
  vkCmdBeginRendering(cmd, &ri);
  VkViewport viewport{0, 0, float(size.width), float(size.height), 0, 1};
  VkRect2D scissor{{0, 0}, {size.width, size.height}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  p.bind(cmd);
  gpu::DescriptorWriter().sampled_image(0, source, sampler).push(ctx, cmd, p);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
}

float bias_value(uint32_t x, uint32_t y) { return float((x * 7 + y * 3) % 5) * 0.25f; }

// CPU reference of the four passes.
std::vector<float> expected(uint32_t w, uint32_t h, float frame) {
  std::vector<float> field(size_t(w) * h), out(size_t(w) * h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) field[y * w + x] = 0.01f * float(x) + 0.1f * float(y) + frame;
  for (int y = 0; y < int(h); ++y)
    for (int x = 0; x < int(w); ++x) {
      float sum = 0.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          sum += field[std::clamp(y + dy, 0, int(h) - 1) * w + std::clamp(x + dx, 0, int(w) - 1)];
      out[y * w + x] = 2.0f * (sum / 9.0f) + bias_value(x, y);
    }
  return out;
}

class RenderGraphVulkan : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!any_vulkan_device()) GTEST_SKIP() << "no Vulkan device";
    errors_before_ = gpu::total_validation_errors();
    gpu::ContextDesc desc;
    desc.validation = true;
    ctx_ = std::make_unique<gpu::Context>(desc);
    ASSERT_TRUE(ctx_->validation_enabled());
    const gpu::ShaderCompiler compiler = test_shaders(*ctx_);
    fill_ = gpu::Pipeline::compute(*ctx_, compiler, {.shader = "fill.comp", .name = "fill"});
    blur_ = gpu::Pipeline::compute(*ctx_, compiler, {.shader = "blur.comp", .name = "blur"});
    composite_ = gpu::Pipeline::compute(*ctx_, compiler, {.shader = "composite.comp", .name = "composite"});
    accumulate_ = gpu::Pipeline::compute(*ctx_, compiler, {.shader = "accumulate.comp", .name = "accumulate"});
    mip_step_ = gpu::Pipeline::compute(*ctx_, compiler, {.shader = "mip_step.comp", .name = "mip step"});
    mip_first_ = gpu::Pipeline::compute(*ctx_, compiler,
                                        {.shader = "mip_step.comp", .defines = {{"FIRST_LEVEL", "1"}}, .name = "mip first"});
    sampler_ = ctx_->samplers().get(gpu::SamplerDesc::nearest_clamp());
  }
  void TearDown() override {
    if (!ctx_) return;
    ctx_->wait_idle();
    EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
    fill_.reset();
    blur_.reset();
    composite_.reset();
    accumulate_.reset();
    mip_step_.reset();
    mip_first_.reset();
    resources_.reset();
    ctx_.reset();
    EXPECT_EQ(gpu::total_validation_errors(), errors_before_) << "validation errors while tearing down";
  }

  // Persistent (imported) resources for one output size.
  struct Persistent {
    gpu::Image bias;
    gpu::Buffer readback;
  };
  void make_persistent(uint32_t w, uint32_t h) {
    resources_ = std::make_unique<Persistent>();
    resources_->bias =
        gpu::Image(*ctx_, gpu::ImageDesc::tex2d(w, h, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "bias"));
    std::vector<float> bias(size_t(w) * h);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) bias[y * w + x] = bias_value(x, y);
    resources_->bias.upload({{bias.data(), bias.size() * sizeof(float)}});
    resources_->readback = gpu::Buffer(*ctx_, {VkDeviceSize(w) * h * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                               gpu::MemoryUsage::Readback, "readback"});
  }

  // The frame: fill -> blur -> composite -> readback, and "debug" that nobody consumes.
  RenderGraph build(VkExtent2D size, float frame) {
    RenderGraph g(size);
    const TextureDesc r32 = TextureDesc::relative(VK_FORMAT_R32_SFLOAT);
    TextureHandle bias =
        g.import_texture("bias", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, size.width, size.height),
                         resources_->bias.handle(), resources_->bias.view(), ResourceState::shader_read_only());
    // The host reads the buffer after each frame: that is the state a frame finds it in, and the
    // one it leaves it in (so a frame in flight waits for the previous frame's copy).
    BufferHandle readback = g.import_buffer("readback", resources_->readback.handle(), resources_->readback.size(),
                                            ResourceState::host_read(), ResourceState::host_read());
    TextureHandle field = g.create_texture("field", r32);
    TextureHandle blurred = g.create_texture("blurred", r32);
    TextureHandle out = g.create_texture("out", r32);
    TextureHandle debug = g.create_texture("debug", r32);

    g.add_pass(
        "fill", Queue::Compute, [&](PassBuilder& b) { field = b.write(field, Usage::StorageWrite); },
        [this, field, frame](PassContext& c) { fill(c.cmd(), c.view(field), c.extent(field), frame); });
    g.add_pass(
        "blur", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(field, Usage::Sampled);
          blurred = b.write(blurred, Usage::StorageWrite);
        },
        [this, field, blurred](PassContext& c) {
          dispatch(*ctx_, c.cmd(), blur_,
                   gpu::DescriptorWriter().sampled_image(0, c.view(field), sampler_).storage_image(1, c.view(blurred)),
                   c.extent(blurred));
        });
    g.add_pass(
        "debug", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(field, Usage::Sampled);
          debug = b.write(debug, Usage::StorageWrite);
        },
        [this](PassContext&) { debug_ran_ = true; });
    if (probe_) {
      // A pass present only in some frames (lightning, a debug view): its own transient, kept by its side effect.
      TextureHandle probe = g.create_texture("probe", r32);
      g.add_pass(
          "probe", Queue::Compute,
          [&](PassBuilder& b) {
            probe = b.write(probe, Usage::StorageWrite);
            b.side_effect();
          },
          [this, probe, frame](PassContext& c) { fill(c.cmd(), c.view(probe), c.extent(probe), frame); });
    }
    if (import_reader_) {
      // A pass on imported resources alone, present only in some frames (a light grid rebuilt when the sun
      // moves): the transients are those of the frames without it.
      g.add_pass(
          "import reader", Queue::Compute,
          [&](PassBuilder& b) {
            b.read(bias, Usage::Sampled);
            b.side_effect();
          },
          [this](PassContext&) { import_reader_ran_ = true; });
    }
    g.add_pass(
        "composite", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(blurred, Usage::StorageRead);
          b.read(bias, Usage::Sampled);
          out = b.write(out, Usage::StorageWrite);
        },
        [this, blurred, bias, out](PassContext& c) {
          dispatch(*ctx_, c.cmd(), composite_,
                   gpu::DescriptorWriter()
                       .storage_image(0, c.view(blurred))
                       .sampled_image(1, c.view(bias), sampler_)
                       .storage_image(2, c.view(out)),
                   c.extent(out));
        });
    g.add_pass(
        "readback", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(out, Usage::TransferSrc);
          readback = b.write(readback, Usage::TransferDst);
        },
        [out, readback](PassContext& c) {
          VkBufferImageCopy region{};
          region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          region.imageExtent = c.extent(out);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(out), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(readback), 1,
                                 &region);
        });
    if (late_reader_) {
      // Reads a transient after its former last use: the memory's last use in the frame changes.
      g.add_pass(
          "late reader", Queue::Compute,
          [&](PassBuilder& b) {
            b.read(out, Usage::Sampled);
            b.side_effect();
          },
          [](PassContext&) {});
    }
    return g;
  }

  // Runs one frame and compares the readback with the CPU reference.
  void run_frame(Executor& executor, VkExtent2D size, float frame) {
    RenderGraph g = build(size, frame);
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    check_readback(size, frame);
  }
  void check_readback(VkExtent2D size, float frame) {
    std::vector<float> got(size_t(size.width) * size.height);
    resources_->readback.download(got.data(), got.size() * sizeof(float));
    const std::vector<float> want = expected(size.width, size.height, frame);
    size_t bad = 0;
    for (size_t i = 0; i < got.size(); ++i)
      if (std::fabs(got[i] - want[i]) > 1e-4f * std::max(1.0f, std::fabs(want[i]))) {
        if (bad++ < 5)
          ADD_FAILURE() << "frame " << frame << " texel " << i << ": got " << got[i] << ", want " << want[i];
      }
    EXPECT_EQ(bad, 0u) << "frame " << frame;
  }

  std::unique_ptr<gpu::Context> ctx_;
  // fill.comp writes v(x, y) = 0.01 x + 0.1 y + frame into `field`.
  void fill(VkCommandBuffer cmd, VkImageView field, VkExtent3D size, float frame) {
    fill_.bind(cmd);
    gpu::DescriptorWriter().storage_image(0, field).push(*ctx_, cmd, fill_);
    fill_.push_constants(cmd, frame);
    fill_.dispatch_threads(cmd, size.width, size.height);
  }

  gpu::Pipeline fill_, blur_, composite_, accumulate_, mip_step_, mip_first_;
  bool probe_ = false;
  bool import_reader_ = false, import_reader_ran_ = false, late_reader_ = false;
  VkSampler sampler_ = VK_NULL_HANDLE;
  std::unique_ptr<Persistent> resources_;
  bool debug_ran_ = false;
  uint32_t errors_before_ = 0;
};

}  // namespace

TEST_F(RenderGraphVulkan, FourPassGraphOverSeveralFrames) {
  const VkExtent2D size{37, 23};  // not a multiple of the 8x8 work group: bounds checks matter
  make_persistent(size.width, size.height);
  Executor executor(*ctx_);
  run_frame(executor, size, 0.0f);
  const CompiledGraph& c = executor.compiled();
  ASSERT_EQ(c.passes.size(), 4u);
  EXPECT_EQ(c.culled, std::vector<std::string>{"debug"});
  uint32_t field = 0, out = 0, blurred = 0;
  for (uint32_t i = 0; i < c.resources.size(); ++i) {
    if (c.resources[i].name == "field") field = i;
    if (c.resources[i].name == "out") out = i;
    if (c.resources[i].name == "blurred") blurred = i;
  }
  // field lives in fill..blur, out in composite..readback: the device's sizes allow sharing.
  EXPECT_TRUE(c.shares_memory(field, out)) << c.to_text();
  EXPECT_FALSE(c.shares_memory(field, blurred));
  const VkImage field_image = executor.texture(field).image;
  const VkImage out_image = executor.texture(out).image;
  EXPECT_NE(field_image, out_image);  // two images, one memory range

  for (int frame = 1; frame < 4; ++frame) run_frame(executor, size, float(frame));

  // Same shape every frame: compiled once, images created once, and the same images reused.
  EXPECT_EQ(executor.compile_count(), 1u);
  EXPECT_EQ(executor.images_created(), 3u);
  EXPECT_EQ(executor.memory_blocks_created(), 2u);
  EXPECT_EQ(executor.texture(field).image, field_image);
  EXPECT_FALSE(debug_ran_);

  if (ctx_->info().timestamps) {
    const std::vector<PassTiming> timings = executor.timings();
    ASSERT_EQ(timings.size(), 4u);
    for (const PassTiming& t : timings) {
      EXPECT_GT(t.ms, 0.0) << t.name;
      std::printf("  %-10s %.3f ms\n", t.name.c_str(), t.ms);  // for the log; never asserted
    }
    EXPECT_EQ(timings[0].name, "fill");
    EXPECT_GT(executor.pass_ms("composite"), 0.0);
    EXPECT_LT(executor.pass_ms("debug"), 0.0);  // culled: no timing
    // run_frame waits for each frame: the newest completed one is the last, frame 4, with the same passes.
    const Executor::CompletedTimings done = executor.latest_completed_timings();
    EXPECT_EQ(done.frame, 4u);
    ASSERT_EQ(done.passes.size(), 4u);
    EXPECT_EQ(done.passes[0].name, "fill");
  }
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

// A pass's timestamps bracket its own work: on lavapipe a timestamp is taken when its rasterizer next
// runs (at a later flush) while a dispatch runs at once, so a single-dispatch compute pass after a draw
// read ~0 ms and its time went to no pass (the cloud light grid: 0.01 ms measured, 100 ms real). A
// draw, then two compute passes, one 1024x the other's work: the large one must measure as larger, and
// on a CPU device the passes must account for most of the frame's wall time. (Without the executor's
// flush after each timestamp: large 0.16 ms, small 0.22 ms, passes / wall 0.39.)
TEST_F(RenderGraphVulkan, ComputePassTimingsMeasureTheirOwnWork) {
  if (!ctx_->info().timestamps) GTEST_SKIP() << "no timestamps on this queue";
  const gpu::Pipeline shade = gpu::Pipeline::graphics(*ctx_, test_shaders(*ctx_),
                                                      {.vertex = "fullscreen.vert",
                                                       .fragment = "shade.frag",
                                                       .color_formats = {VK_FORMAT_R32_SFLOAT},
                                                       .name = "shade"});
  Executor executor(*ctx_);
  const VkExtent2D size{64, 64};
  const TextureDesc small_desc = TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, 64, 64);
  const TextureDesc large_desc = TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, 2048, 2048);
  std::vector<double> small_ms, large_ms, share;
  for (int frame = 0; frame < 5; ++frame) {
    RenderGraph g(size);
    TextureHandle small = g.create_texture("small", small_desc), large = g.create_texture("large", large_desc);
    TextureHandle color = g.create_texture("color", large_desc);
    g.add_pass(
        "small", Queue::Compute,
        [&](PassBuilder& b) {
          small = b.write(small, Usage::StorageWrite);
          b.side_effect();
        },
        [this, small](PassContext& c) { fill(c.cmd(), c.view(small), c.extent(small), 0.0f); });
    g.add_pass(
        "draw", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(small, Usage::Sampled);
          color = b.write(color, Usage::ColorAttachment);
          b.side_effect();
        },
        [&, small, color](PassContext& c) {
          draw_fullscreen(*ctx_, c.cmd(), shade, c.view(small), sampler_, c.view(color), c.extent(color));
        });
    g.add_pass(
        "large", Queue::Compute,
        [&](PassBuilder& b) {
          large = b.write(large, Usage::StorageWrite);
          b.side_effect();
        },
        [this, large](PassContext& c) { fill(c.cmd(), c.view(large), c.extent(large), 0.0f); });
    const auto t0 = std::chrono::steady_clock::now();
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (frame == 0) continue;  // first frame: image creation and pipeline warm-up
    small_ms.push_back(executor.pass_ms("small"));
    large_ms.push_back(executor.pass_ms("large"));
    share.push_back((small_ms.back() + executor.pass_ms("draw") + large_ms.back()) / wall_ms);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf("  small %.3f ms, large %.3f ms (after a draw), passes / wall %.2f (medians)\n", median(small_ms), median(large_ms),
              median(share));
  EXPECT_GT(median(small_ms), 0.0);
  EXPECT_GT(median(large_ms), 4.0 * median(small_ms));
  if (ctx_->info().is_cpu()) EXPECT_GT(median(share), 0.5);  // a GPU's submit overhead can dwarf 4M texel writes
}

// compute writes a storage image -> a fragment shader samples it into a color attachment -> copy.
TEST_F(RenderGraphVulkan, ComputeToFragmentToReadback) {
  const VkExtent2D size{37, 23};
  make_persistent(size.width, size.height);
  const gpu::Pipeline shade = gpu::Pipeline::graphics(*ctx_, test_shaders(*ctx_),
                                                      {.vertex = "fullscreen.vert",
                                                       .fragment = "shade.frag",
                                                       .color_formats = {VK_FORMAT_R32_SFLOAT},
                                                       .name = "shade"});
  Executor executor(*ctx_);
  for (int frame = 0; frame < 3; ++frame) {
    RenderGraph g(size);
    BufferHandle readback = g.import_buffer("readback", resources_->readback.handle(), resources_->readback.size(),
                                            ResourceState::undefined(), ResourceState::host_read());
    TextureHandle field = g.create_texture("field", TextureDesc::relative(VK_FORMAT_R32_SFLOAT));
    TextureHandle color = g.create_texture("color", TextureDesc::relative(VK_FORMAT_R32_SFLOAT));
    g.add_pass(
        "fill", Queue::Compute, [&](PassBuilder& b) { field = b.write(field, Usage::StorageWrite); },
        [&, field](PassContext& c) { fill(c.cmd(), c.view(field), c.extent(field), float(frame)); });
    g.add_pass(
        "shade", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(field, Usage::Sampled);
          color = b.write(color, Usage::ColorAttachment);
        },
        [&, field, color](PassContext& c) {
          draw_fullscreen(*ctx_, c.cmd(), shade, c.view(field), sampler_, c.view(color), c.extent(color));
        });
    g.add_pass(
        "readback", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(color, Usage::TransferSrc);
          readback = b.write(readback, Usage::TransferDst);
        },
        [color, readback](PassContext& c) {
          VkBufferImageCopy region{};
          region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          region.imageExtent = c.extent(color);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(color), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(readback), 1,
                                 &region);
        });
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    std::vector<float> got(size_t(size.width) * size.height);
    resources_->readback.download(got.data(), got.size() * sizeof(float));
    size_t bad = 0;
    for (uint32_t y = 0; y < size.height; ++y)
      for (uint32_t x = 0; x < size.width; ++x) {
        const float want = 3.0f * (0.01f * float(x) + 0.1f * float(y) + float(frame)) + 1.0f;
        if (std::fabs(got[y * size.width + x] - want) > 1e-4f * std::max(1.0f, want) && bad++ < 5)
          ADD_FAILURE() << "frame " << frame << " (" << x << ", " << y << "): got " << got[y * size.width + x]
                        << ", want " << want;
      }
    EXPECT_EQ(bad, 0u);
  }
  const Barrier* sampled = nullptr;
  for (const Barrier& b : executor.compiled().find_pass("shade")->barriers)
    if (b.name == "field") sampled = &b;
  ASSERT_NE(sampled, nullptr);
  EXPECT_EQ(sampled->dst_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(executor.compile_count(), 1u);
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

// Several frames recorded and submitted before any completes: the same transient images serve
// every frame, so each frame's first use of a block must wait for the previous frame's last use.
TEST_F(RenderGraphVulkan, FramesInFlightShareTransientsSafely) {
  const VkExtent2D size{37, 23};
  make_persistent(size.width, size.height);
  Executor executor(*ctx_);
  VkDevice dev = ctx_->device();
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.queueFamilyIndex = ctx_->queue_family();
  VkCommandPool pool;
  VK_CHECK(vkCreateCommandPool(dev, &pi, nullptr, &pool));
  constexpr uint32_t kFrames = 3;
  VkCommandBuffer cmds[kFrames];
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = kFrames;
  VK_CHECK(vkAllocateCommandBuffers(dev, &ai, cmds));
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  VK_CHECK(vkCreateFence(dev, &fi, nullptr, &fence));

  std::vector<RenderGraph> graphs;
  for (uint32_t f = 0; f < kFrames; ++f) graphs.push_back(build(size, float(10 + f)));
  for (uint32_t f = 0; f < kFrames; ++f) {
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    VK_CHECK(vkBeginCommandBuffer(cmds[f], &bi));
    executor.execute(graphs[f], cmds[f]);
    VK_CHECK(vkEndCommandBuffer(cmds[f]));
  }
  for (uint32_t f = 0; f < kFrames; ++f) {  // one submission per frame, in order, fence on the last
    VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cbi.commandBuffer = cmds[f];
    VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    si.commandBufferInfoCount = 1;
    si.pCommandBufferInfos = &cbi;
    ctx_->submit(si, f + 1 == kFrames ? fence : VK_NULL_HANDLE);
  }
  VK_CHECK(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX));
  check_readback(size, float(10 + kFrames - 1));  // the last frame's copy wins

  // The same frames back to back in ONE command buffer: synchronization validation (which in this
  // layer version checks within a command buffer, not across submissions) then sees every
  // frame-to-frame hand-over of the shared transients and of the imported buffer.
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
    for (uint32_t f = 0; f < kFrames; ++f) executor.execute(graphs[f], cmd);
  });
  check_readback(size, float(10 + kFrames - 1));
  EXPECT_EQ(executor.compile_count(), 1u);
  vkDestroyFence(dev, fence, nullptr);
  vkDestroyCommandPool(dev, pool, nullptr);
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

// Depth: written as an attachment (cleared by dynamic rendering), then copied out. The layout the
// pass renders in comes from the graph (PassContext::layout), never hard-coded.
TEST_F(RenderGraphVulkan, DepthAttachmentThenCopy) {
  const VkExtent2D size{16, 8};
  gpu::Buffer readback(*ctx_, {VkDeviceSize(size.width) * size.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               gpu::MemoryUsage::Readback, "depth readback"});
  Executor executor(*ctx_);
  for (int frame = 0; frame < 2; ++frame) {
    RenderGraph g(size);
    BufferHandle out = g.import_buffer("depth readback", readback.handle(), readback.size(), ResourceState::host_read(),
                                       ResourceState::host_read());
    TextureHandle depth = g.create_texture("depth", TextureDesc::relative(VK_FORMAT_D32_SFLOAT));
    const float clear = 0.25f + 0.5f * float(frame);
    g.add_pass(
        "depth", Queue::Graphics, [&](PassBuilder& b) { depth = b.write(depth, Usage::DepthWrite); },
        [depth, clear](PassContext& c) {
          VkRenderingAttachmentInfo d{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
          d.imageView = c.view(depth);
          d.imageLayout = c.layout(depth);
          d.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
          d.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
          d.clearValue.depthStencil = {clear, 0};
          VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
          ri.renderArea = {{0, 0}, {c.extent(depth).width, c.extent(depth).height}};
          ri.layerCount = 1;
          ri.pDepthAttachment = &d;
          vkCmdBeginRendering(c.cmd(), &ri);
          vkCmdEndRendering(c.cmd());
        });
    g.add_pass(
        "copy", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(depth, Usage::TransferSrc);
          out = b.write(out, Usage::TransferDst);
        },
        [depth, out](PassContext& c) {
          VkBufferImageCopy region{};
          region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
          region.imageExtent = c.extent(depth);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(depth), c.layout(depth), c.buffer(out), 1, &region);
        });
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    std::vector<float> got(size_t(size.width) * size.height);
    readback.download(got.data(), got.size() * sizeof(float));
    for (float v : got) ASSERT_FLOAT_EQ(v, clear);
  }
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

TEST_F(RenderGraphVulkan, NewShapeRecompilesAndStaysCorrect) {
  Executor executor(*ctx_);
  make_persistent(37, 23);
  run_frame(executor, {37, 23}, 1.0f);
  run_frame(executor, {37, 23}, 2.0f);
  EXPECT_EQ(executor.compile_count(), 1u);
  ctx_->wait_idle();
  make_persistent(64, 40);  // a resize: the imports change size, so the graph's hash changes
  run_frame(executor, {64, 40}, 3.0f);
  run_frame(executor, {64, 40}, 4.0f);
  EXPECT_EQ(executor.compile_count(), 2u);
  EXPECT_EQ(executor.images_created(), 6u);
  EXPECT_EQ(executor.compiled().output_size.width, 64u);
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

// Budget-mode toggles, debug views, a pass present only while lightning strikes: switching back and
// forth between shapes already seen compiles nothing and creates no image or memory.
TEST_F(RenderGraphVulkan, SwitchingBetweenSeenShapesAllocatesNothing) {
  const VkExtent2D size{37, 23};
  make_persistent(size.width, size.height);
  Executor executor(*ctx_);
  run_frame(executor, size, 0.0f);
  probe_ = true;
  run_frame(executor, size, 1.0f);
  ASSERT_NE(executor.compiled().find_pass("probe"), nullptr);
  const uint32_t compiles = executor.compile_count(), images = executor.images_created(),
                 blocks = executor.memory_blocks_created();
  EXPECT_EQ(compiles, 2u);
  EXPECT_EQ(executor.shape_count(), 2u);
  for (int i = 2; i < 8; ++i) {
    probe_ = (i % 2) == 1;
    run_frame(executor, size, float(i));
    EXPECT_EQ(executor.compiled().find_pass("probe") != nullptr, probe_);
  }
  EXPECT_EQ(executor.compile_count(), compiles);
  EXPECT_EQ(executor.images_created(), images);
  EXPECT_EQ(executor.memory_blocks_created(), blocks);
  EXPECT_EQ(executor.shape_count(), 2u);
}

// Shapes that differ only in a pass on imported resources share their transient objects: the new shape
// is compiled, but nothing is created on the device; frames alternating between them stay correct and
// clean under synchronization validation. A shape whose transient is last used by another stage does not
// share them (the next frame's first use of that memory waits for that stage).
TEST_F(RenderGraphVulkan, ShapesOfOneTransientLayoutShareItsObjects) {
  const VkExtent2D size{37, 23};
  make_persistent(size.width, size.height);
  Executor executor(*ctx_);
  run_frame(executor, size, 0.0f);
  const uint32_t images = executor.images_created(), blocks = executor.memory_blocks_created();
  for (int i = 1; i < 7; ++i) {
    import_reader_ = (i % 2) == 1;
    import_reader_ran_ = false;
    run_frame(executor, size, float(i));
    EXPECT_EQ(import_reader_ran_, import_reader_);
  }
  EXPECT_EQ(executor.compile_count(), 2u);
  EXPECT_EQ(executor.shape_count(), 2u);
  EXPECT_EQ(executor.layout_count(), 1u);
  EXPECT_EQ(executor.layouts_created(), 1u);
  EXPECT_EQ(executor.images_created(), images);
  EXPECT_EQ(executor.memory_blocks_created(), blocks);
  // The two shapes back to back in one command buffer: synchronization validation sees each hand-over of
  // the shared transients from one shape to the other.
  std::vector<RenderGraph> graphs;
  for (int f = 0; f < 4; ++f) {
    import_reader_ = (f % 2) == 0;
    graphs.push_back(build(size, float(20 + f)));
  }
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
    for (RenderGraph& g : graphs) executor.execute(g, cmd);
  });
  check_readback(size, 23.0f);
  EXPECT_EQ(executor.compile_count(), 2u);

  import_reader_ = false;
  late_reader_ = true;
  run_frame(executor, size, 7.0f);
  EXPECT_EQ(executor.layout_count(), 2u);
  late_reader_ = false;
  run_frame(executor, size, 8.0f);
  EXPECT_EQ(executor.layouts_created(), 2u);
  EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
}

// History resources on the device: accumulation over frames through the ping-pong pair, the valid
// flag on the first frame and after a camera cut, synchronization validation clean.
TEST_F(RenderGraphVulkan, HistoryAccumulatesAcrossFrames) {
  const VkExtent2D size{21, 13};
  gpu::Buffer readback(*ctx_, {VkDeviceSize(size.width) * size.height * sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               gpu::MemoryUsage::Readback, "history readback"});
  GpuHistory history("accumulation", VK_FORMAT_R32_SFLOAT, 1.0f,
                     VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  Executor executor(*ctx_);
  std::vector<float> seen;
  for (int frame = 0; frame < 5; ++frame) {
    if (frame == 3) history.invalidate();  // camera cut: start again
    RenderGraph g(size);
    BufferHandle rb = g.import_buffer("readback", readback.handle(), readback.size(), ResourceState::host_read(),
                                      ResourceState::host_read());
    HistoryHandles h = history.import(*ctx_, g);
    g.add_pass(
        "accumulate", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(h.previous, Usage::StorageRead);
          h.current = b.write(h.current, Usage::StorageWrite);
        },
        [this, h](PassContext& c) {
          accumulate_.bind(c.cmd());
          gpu::DescriptorWriter().storage_image(0, c.view(h.previous)).storage_image(1, c.view(h.current)).push(*ctx_, c.cmd(), accumulate_);
          struct {
            float valid, add;
          } push{h.valid ? 1.0f : 0.0f, 1.0f};
          accumulate_.push_constants(c.cmd(), &push, sizeof push);
          accumulate_.dispatch_threads(c.cmd(), c.extent(h.current).width, c.extent(h.current).height);
        });
    g.add_pass(
        "readback", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(h.current, Usage::TransferSrc);
          rb = b.write(rb, Usage::TransferDst);
        },
        [cur = h.current, rb](PassContext& c) {
          VkBufferImageCopy region{};
          region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          region.imageExtent = c.extent(cur);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(cur), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb), 1, &region);
        });
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    std::vector<float> got(size_t(size.width) * size.height);
    readback.download(got.data(), got.size() * sizeof(float));
    for (float v : got) ASSERT_EQ(v, got[0]);
    seen.push_back(got[0]);
  }
  EXPECT_EQ(seen, (std::vector<float>{1, 2, 3, 1, 2}));
  EXPECT_LE(executor.compile_count(), 2u);  // the first frame (undefined start), then one steady shape
}

// The documented rule for mip chains: the pass declares the whole image and places its own barrier
// between mips; mip_view gives it single-mip views. The top mip is the mean of mip 0.
TEST_F(RenderGraphVulkan, MipChainBuiltPassByPass) {
  const VkExtent2D size{16, 16};
  gpu::Buffer readback(*ctx_, {sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "mip readback"});
  RenderGraph g(size);
  TextureDesc desc = TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, 16, 16);
  desc.mips = 5;
  TextureHandle chain = g.create_texture("chain", desc);
  BufferHandle rb = g.import_buffer("readback", readback.handle(), readback.size(), ResourceState::host_read(),
                                    ResourceState::host_read());
  g.add_pass(
      "build mips", Queue::Compute, [&](PassBuilder& b) { chain = b.write(chain, Usage::StorageWrite); },
      [this, chain](PassContext& c) {
        for (uint32_t m = 0; m < 5; ++m) {
          if (m > 0) {
            // Inside the pass, on purpose: mip m reads what this pass just wrote into mip m - 1.
            gpu::cmd_image_barrier(c.cmd(), c.image(chain), {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, 1, 0, 1},
                                   VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
          }
          const gpu::Pipeline& p = m == 0 ? mip_first_ : mip_step_;
          p.bind(c.cmd());
          gpu::DescriptorWriter set;
          if (m > 0) set.storage_image(0, c.mip_view(chain, m - 1));
          set.storage_image(1, c.mip_view(chain, m)).push(*ctx_, c.cmd(), p);
          p.dispatch_threads(c.cmd(), 16u >> m, 16u >> m);
        }
      });
  g.add_pass(
      "read top mip", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(chain, Usage::TransferSrc);
        rb = b.write(rb, Usage::TransferDst);
      },
      [chain, rb](PassContext& c) {
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 4, 0, 1};
        region.imageExtent = {1, 1, 1};
        vkCmdCopyImageToBuffer(c.cmd(), c.image(chain), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb), 1, &region);
      });
  Executor executor(*ctx_);
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
  float top = 0;
  readback.download(&top, sizeof top);
  EXPECT_FLOAT_EQ(top, 127.5f);  // mean of x + 16 y over 16 x 16
}
