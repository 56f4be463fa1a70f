// CPU cost of the render graph per frame: declaring + hashing (what a frame with an unchanged shape
// pays) and declaring + compiling (what a shape change pays). Numbers come from a manual run:
//   build-graph/tests/engine/render/graph/render_graph_bench
#include <benchmark/benchmark.h>

#include <string>

#include "engine/render/graph/render_graph.h"

using namespace cumulo::render;

namespace {

// A frame shaped like the cloud frame of DESIGN.md: geometry, sky, light grid, near/far march,
// composite, temporal, tonemap, plus `extra` post passes; one debug pass is culled.
RenderGraph frame_graph(int extra) {
  RenderGraph g({960, 540});
  const TextureDesc hdr = TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT);
  TextureHandle out = g.import_texture("swapchain", TextureDesc::relative(VK_FORMAT_B8G8R8A8_UNORM), VK_NULL_HANDLE,
                                       VK_NULL_HANDLE, ResourceState::acquired(), ResourceState::present());
  TextureHandle history =
      g.import_texture("cloud_history", hdr, VK_NULL_HANDLE, VK_NULL_HANDLE, ResourceState::shader_read_only());
  TextureHandle grid = g.import_texture("light_grid", TextureDesc::absolute(VK_FORMAT_R16G16_SFLOAT, 256, 256, 32),
                                        VK_NULL_HANDLE, VK_NULL_HANDLE, ResourceState::shader_read_only());
  TextureHandle color = g.create_texture("scene", hdr);
  TextureHandle depth = g.create_texture("depth", TextureDesc::relative(VK_FORMAT_D32_SFLOAT));
  TextureHandle near = g.create_texture("near", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT, 0.5f));
  TextureHandle far = g.create_texture("far", hdr);
  TextureHandle clouds = g.create_texture("clouds", hdr);
  TextureHandle debug = g.create_texture("debug", hdr);
  g.add_pass(
      "geometry", Queue::Graphics,
      [&](PassBuilder& b) {
        color = b.write(color, Usage::ColorAttachment);
        depth = b.write(depth, Usage::DepthWrite);
      },
      nullptr);
  g.add_pass(
      "sky", Queue::Graphics,
      [&](PassBuilder& b) {
        color = b.read_write(color, Usage::ColorAttachment);
        b.read(depth, Usage::DepthRead);
      },
      nullptr);
  g.add_pass(
      "light_grid", Queue::Compute, [&](PassBuilder& b) { grid = b.read_write(grid, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "march_near", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(depth, Usage::Sampled);
        b.read(grid, Usage::Sampled);
        near = b.write(near, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "march_far", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(depth, Usage::Sampled);
        b.read(grid, Usage::Sampled);
        far = b.write(far, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "debug_view", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(far, Usage::Sampled);
        debug = b.write(debug, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "composite", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(near, Usage::Sampled);
        b.read(far, Usage::Sampled);
        clouds = b.write(clouds, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "temporal", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(clouds, Usage::StorageRead);
        history = b.read_write(history, Usage::StorageWrite);
      },
      nullptr);
  TextureHandle last = color;
  for (int i = 0; i < extra; ++i) {
    TextureHandle next = g.create_texture("post" + std::to_string(i), hdr);
    g.add_pass(
        "post" + std::to_string(i), Queue::Compute,
        [&](PassBuilder& b) {
          b.read(last, Usage::Sampled);
          b.read(history, Usage::Sampled);
          next = b.write(next, Usage::StorageWrite);
        },
        nullptr);
    last = next;
  }
  g.add_pass(
      "tonemap", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(last, Usage::Sampled);
        b.read(history, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  return g;
}

void BM_DeclareAndHash(benchmark::State& state) {
  for (auto _ : state) {
    RenderGraph g = frame_graph(int(state.range(0)));
    benchmark::DoNotOptimize(g.hash());
  }
}
BENCHMARK(BM_DeclareAndHash)->Arg(0)->Arg(16);

void BM_DeclareAndCompile(benchmark::State& state) {
  for (auto _ : state) {
    RenderGraph g = frame_graph(int(state.range(0)));
    CompiledGraph c = g.compile();
    benchmark::DoNotOptimize(c.passes.data());
  }
}
BENCHMARK(BM_DeclareAndCompile)->Arg(0)->Arg(16);

}  // namespace

BENCHMARK_MAIN();
