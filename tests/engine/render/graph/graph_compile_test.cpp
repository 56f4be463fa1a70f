// The compiled render graph, with no device: culling, order, exact barriers, aliasing, dumps.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/render/graph/executor.h"
#include "engine/render/graph/render_graph.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

constexpr VkExtent2D kSize{160, 90};
const TextureDesc kRgba16 = TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT);

TextureHandle import_swapchain(RenderGraph& g) {
  return g.import_texture("swapchain", TextureDesc::absolute(VK_FORMAT_B8G8R8A8_UNORM, kSize.width, kSize.height),
                          VK_NULL_HANDLE, VK_NULL_HANDLE,
                          {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0},
                          ResourceState::present());
}

const Barrier* find_barrier(const std::vector<Barrier>& barriers, const std::string& name) {
  for (const Barrier& b : barriers)
    if (b.name == name) return &b;
  return nullptr;
}

uint32_t index_of(const CompiledGraph& c, const std::string& name) {
  for (uint32_t i = 0; i < c.resources.size(); ++i)
    if (c.resources[i].name == name) return i;
  ADD_FAILURE() << "no resource " << name;
  return 0;
}

std::string compile_error(const RenderGraph& g) {
  try {
    g.compile();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RenderGraphCompile, CullsPassesWhoseOutputNobodyReads) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  TextureHandle a = g.create_texture("a", kRgba16);
  TextureHandle unused = g.create_texture("unused", kRgba16);
  TextureHandle dead_end = g.create_texture("dead_end", kRgba16);
  std::vector<std::string> ran;
  g.add_pass(
      "produce", Queue::Compute, [&](PassBuilder& b) { a = b.write(a, Usage::StorageWrite); },
      [&](PassContext& c) { ran.push_back(c.pass_name()); });
  g.add_pass(
      "orphan", Queue::Compute, [&](PassBuilder& b) { unused = b.write(unused, Usage::StorageWrite); },
      [&](PassContext& c) { ran.push_back(c.pass_name()); });
  // A chain that leads nowhere: both passes must go, walking back from the outputs.
  g.add_pass(
      "chain1", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(a, Usage::Sampled);
        unused = b.write(unused, Usage::StorageWrite);
      },
      [&](PassContext& c) { ran.push_back(c.pass_name()); });
  g.add_pass(
      "chain2", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(unused, Usage::Sampled);
        dead_end = b.write(dead_end, Usage::StorageWrite);
      },
      [&](PassContext& c) { ran.push_back(c.pass_name()); });
  g.add_pass(
      "present", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(a, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      [&](PassContext& c) { ran.push_back(c.pass_name()); });

  CompiledGraph c = g.compile();
  ASSERT_EQ(c.passes.size(), 2u);
  EXPECT_EQ(c.passes[0].name, "produce");
  EXPECT_EQ(c.passes[1].name, "present");
  EXPECT_EQ(c.culled, (std::vector<std::string>{"orphan", "chain1", "chain2"}));
  EXPECT_EQ(c.find_pass("orphan"), nullptr);
  EXPECT_EQ(c.resources[index_of(c, "dead_end")].first_pass, -1);
  EXPECT_EQ(c.resources[index_of(c, "dead_end")].memory_block, -1);  // nothing allocated for it

  g.execute_without_device(c);
  EXPECT_EQ(ran, (std::vector<std::string>{"produce", "present"}));
}

TEST(RenderGraphCompile, OverwrittenImportedVersionIsNotNeeded) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  g.add_pass(
      "first", Queue::Graphics, [&](PassBuilder& b) { out = b.write(out, Usage::ColorAttachment); }, nullptr);
  g.add_pass(
      "second", Queue::Graphics, [&](PassBuilder& b) { out = b.write(out, Usage::ColorAttachment); }, nullptr);
  g.add_pass(
      "blend", Queue::Graphics, [&](PassBuilder& b) { out = b.read_write(out, Usage::ColorAttachment); }, nullptr);
  CompiledGraph c = g.compile();
  // "second" overwrites without reading, so "first"'s version is never seen; "blend" keeps "second".
  EXPECT_EQ(c.culled, (std::vector<std::string>{"first"}));
  ASSERT_EQ(c.passes.size(), 2u);
  EXPECT_EQ(c.position("second"), 0);
  EXPECT_EQ(c.position("blend"), 1);
}

TEST(RenderGraphCompile, OrderFollowsDependencies) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  TextureHandle depth = g.create_texture("depth", TextureDesc::relative(VK_FORMAT_D32_SFLOAT));
  TextureHandle color = g.create_texture("color", kRgba16);
  TextureHandle clouds = g.create_texture("clouds", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT, 0.5f));
  g.add_pass(
      "geometry", Queue::Graphics,
      [&](PassBuilder& b) {
        depth = b.write(depth, Usage::DepthWrite);
        color = b.write(color, Usage::ColorAttachment);
      },
      nullptr);
  g.add_pass(
      "clouds", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(depth, Usage::Sampled);
        clouds = b.write(clouds, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "composite", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(clouds, Usage::Sampled);
        b.read(color, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  ASSERT_EQ(c.passes.size(), 3u);
  EXPECT_LT(c.position("geometry"), c.position("clouds"));
  EXPECT_LT(c.position("clouds"), c.position("composite"));
  // Relative sizes resolve against the output size.
  EXPECT_EQ(c.resources[index_of(c, "clouds")].extent.width, 80u);
  EXPECT_EQ(c.resources[index_of(c, "clouds")].extent.height, 45u);
  EXPECT_EQ(c.resources[index_of(c, "color")].image_usage,
            VkImageUsageFlags(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT));
  // Depth written by geometry, then sampled by compute: depth-test stages -> compute, layout change.
  const Barrier* d = find_barrier(c.find_pass("clouds")->barriers, "depth");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->src_stages, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT);
  EXPECT_EQ(d->src_access, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  EXPECT_EQ(d->dst_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(d->dst_access, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  EXPECT_EQ(d->old_layout, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
  EXPECT_EQ(d->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

// compute writes a storage image -> fragment samples it into the swapchain -> present.
TEST(RenderGraphCompile, ExactBarriersComputeToFragmentToPresent) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  TextureHandle hdr = g.create_texture("hdr", kRgba16);
  g.add_pass(
      "march", Queue::Compute, [&](PassBuilder& b) { hdr = b.write(hdr, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "tonemap", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(hdr, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  ASSERT_EQ(c.passes.size(), 2u);

  // march: the transient's first use discards, after its own last use in the previous frame.
  ASSERT_EQ(c.passes[0].barriers.size(), 1u);
  const Barrier& discard = c.passes[0].barriers[0];
  EXPECT_EQ(discard.name, "hdr");
  EXPECT_TRUE(discard.discard);
  EXPECT_EQ(discard.src_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(discard.src_access, VK_ACCESS_2_NONE);  // write-after-read: execution dependency only
  EXPECT_EQ(discard.dst_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(discard.dst_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(discard.old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(discard.new_layout, VK_IMAGE_LAYOUT_GENERAL);

  // tonemap: hdr storage write -> sampled read; swapchain acquired -> color attachment.
  ASSERT_EQ(c.passes[1].barriers.size(), 2u);
  const Barrier* h = find_barrier(c.passes[1].barriers, "hdr");
  ASSERT_NE(h, nullptr);
  EXPECT_FALSE(h->discard);
  EXPECT_EQ(h->src_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(h->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(h->dst_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(h->dst_access, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  EXPECT_EQ(h->old_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(h->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  const Barrier* s = find_barrier(c.passes[1].barriers, "swapchain");
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->src_stages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
  EXPECT_EQ(s->src_access, VK_ACCESS_2_NONE);
  EXPECT_EQ(s->dst_stages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
  EXPECT_EQ(s->dst_access, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  EXPECT_EQ(s->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(s->new_layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

  // After the last pass: to PRESENT_SRC, the color write made available.
  ASSERT_EQ(c.final_barriers.size(), 1u);
  const Barrier& p = c.final_barriers[0];
  EXPECT_EQ(p.name, "swapchain");
  EXPECT_EQ(p.src_stages, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT);
  EXPECT_EQ(p.src_access, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  EXPECT_EQ(p.dst_stages, VK_PIPELINE_STAGE_2_NONE);
  EXPECT_EQ(p.dst_access, VK_ACCESS_2_NONE);
  EXPECT_EQ(p.old_layout, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  EXPECT_EQ(p.new_layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
}

TEST(RenderGraphCompile, ReadAfterReadNeedsNoBarrierButLayoutChangesDo) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  TextureHandle t = g.create_texture("t", kRgba16);
  TextureHandle x = g.create_texture("x", kRgba16);
  TextureHandle y = g.create_texture("y", kRgba16);
  g.add_pass(
      "write", Queue::Compute, [&](PassBuilder& b) { t = b.write(t, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "read1", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(t, Usage::Sampled);
        x = b.write(x, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "read2", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(t, Usage::Sampled);
        b.read(x, Usage::Sampled);
        y = b.write(y, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "read3", Queue::Graphics,
      [&](PassBuilder& b) {  // read-only layout change: SHADER_READ_ONLY -> GENERAL
        b.read(t, Usage::StorageRead);
        b.read(y, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  ASSERT_EQ(c.passes.size(), 4u);
  EXPECT_NE(find_barrier(c.find_pass("read1")->barriers, "t"), nullptr);
  EXPECT_EQ(find_barrier(c.find_pass("read2")->barriers, "t"), nullptr);  // read after read, same stage
  const Barrier* r3 = find_barrier(c.find_pass("read3")->barriers, "t");
  ASSERT_NE(r3, nullptr);
  EXPECT_EQ(r3->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(r3->new_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_TRUE(r3->src_stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);  // waits for the compute reads
  EXPECT_EQ(r3->dst_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(r3->dst_access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

TEST(RenderGraphCompile, WriteAfterReadWaitsForTheReaders) {
  RenderGraph g(kSize);
  BufferHandle readback =
      g.import_buffer("readback", VK_NULL_HANDLE, 1024, ResourceState::undefined(), ResourceState::host_read());
  BufferHandle params = g.create_buffer("params", {256});
  TextureHandle t = g.create_texture("t", kRgba16);
  g.add_pass(
      "fill", Queue::Compute, [&](PassBuilder& b) { params = b.write(params, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "draw", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(params, Usage::Uniform, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT);
        t = b.write(t, Usage::ColorAttachment);
      },
      nullptr);
  g.add_pass(
      "refill", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(t, Usage::Sampled);
        params = b.write(params, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "copy", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(params, Usage::TransferSrc);
        readback = b.write(readback, Usage::TransferDst);
      },
      nullptr);
  CompiledGraph c = g.compile();
  ASSERT_EQ(c.passes.size(), 4u);
  const Barrier* raw = find_barrier(c.find_pass("draw")->barriers, "params");
  ASSERT_NE(raw, nullptr);
  EXPECT_FALSE(raw->image);
  EXPECT_EQ(raw->src_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(raw->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  EXPECT_EQ(raw->dst_stages, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT);
  EXPECT_EQ(raw->dst_access, VK_ACCESS_2_UNIFORM_READ_BIT);
  const Barrier* war = find_barrier(c.find_pass("refill")->barriers, "params");
  ASSERT_NE(war, nullptr);
  EXPECT_TRUE(war->src_stages & VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT);  // the reader
  EXPECT_EQ(war->dst_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(war->dst_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  // Readback buffer: transfer write, then made visible to the host after the last pass.
  const Barrier* host = find_barrier(c.final_barriers, "readback");
  ASSERT_NE(host, nullptr);
  EXPECT_EQ(host->src_stages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
  EXPECT_EQ(host->src_access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  EXPECT_EQ(host->dst_stages, VK_PIPELINE_STAGE_2_HOST_BIT);
  EXPECT_EQ(host->dst_access, VK_ACCESS_2_HOST_READ_BIT);
}

// Three transients in a chain: a [0,1], b [1,2], c [2,3]. a and c never live at once.
static RenderGraph chain_graph(std::vector<std::string>* ran = nullptr) {
  RenderGraph g(kSize);
  BufferHandle readback =
      g.import_buffer("readback", VK_NULL_HANDLE, 160 * 90 * 8, ResourceState::undefined(), ResourceState::host_read());
  TextureHandle a = g.create_texture("a", kRgba16);
  TextureHandle b = g.create_texture("b", kRgba16);
  TextureHandle c = g.create_texture("c", kRgba16);
  g.add_pass(
      "fill", Queue::Compute, [&](PassBuilder& p) { a = p.write(a, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "blur", Queue::Compute,
      [&](PassBuilder& p) {
        p.read(a, Usage::Sampled);
        b = p.write(b, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "composite", Queue::Compute,
      [&](PassBuilder& p) {
        p.read(b, Usage::StorageRead);
        c = p.write(c, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "readback", Queue::Compute,
      [&](PassBuilder& p) {
        p.read(c, Usage::TransferSrc);
        readback = p.write(readback, Usage::TransferDst);
      },
      nullptr);
  return g;
}

TEST(RenderGraphCompile, AliasesTransientsWithDisjointLifetimes) {
  RenderGraph g = chain_graph();
  CompiledGraph c = g.compile();
  const uint32_t a = index_of(c, "a"), b = index_of(c, "b"), cc = index_of(c, "c");
  EXPECT_EQ(c.resources[a].first_pass, 0);
  EXPECT_EQ(c.resources[a].last_pass, 1);
  EXPECT_EQ(c.resources[cc].first_pass, 2);
  EXPECT_TRUE(c.shares_memory(a, cc));   // disjoint: [0,1] and [2,3]
  EXPECT_FALSE(c.shares_memory(a, b));   // overlap at pass 1
  EXPECT_FALSE(c.shares_memory(b, cc));  // overlap at pass 2
  EXPECT_EQ(c.memory_blocks.size(), 2u);
  EXPECT_EQ(c.resources[index_of(c, "readback")].memory_block, -1);  // imported: never aliased

  // c's first use discards and waits for a's last use (the sampled read in blur).
  const Barrier* d = find_barrier(c.find_pass("composite")->barriers, "c");
  ASSERT_NE(d, nullptr);
  EXPECT_TRUE(d->discard);
  EXPECT_EQ(d->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(d->src_stages, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(d->src_access, VK_ACCESS_2_NONE);
  // a's first use waits for c's last use in the previous frame (the copy).
  const Barrier* f = find_barrier(c.find_pass("fill")->barriers, "a");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->src_stages, VK_PIPELINE_STAGE_2_TRANSFER_BIT);

  CompileOptions no_alias;
  no_alias.alias_memory = false;
  CompiledGraph separate = g.compile(no_alias);
  EXPECT_FALSE(separate.shares_memory(a, cc));
  EXPECT_EQ(separate.memory_blocks.size(), 3u);

  // Memory types that do not intersect cannot share a block.
  CompileOptions typed;
  typed.memory_query = [](const CompiledResource& r) {
    MemoryQuery q = estimate_memory(r);
    q.memory_type_bits = r.name == "c" ? 0x2u : 0x1u;
    return q;
  };
  CompiledGraph incompatible = g.compile(typed);
  EXPECT_FALSE(incompatible.shares_memory(a, cc));
}

TEST(RenderGraphCompile, MemoryEstimateUsesTheFormatFactsOfGpuFormat) {
  CompiledResource r;
  r.extent = {64, 32, 1};
  r.format = VK_FORMAT_R16G16B16A16_SFLOAT;  // 8 bytes a texel, mips 64x32 + 32x16 + 16x8
  r.mips = 3;
  EXPECT_EQ(estimate_memory(r).size, 8u * (64 * 32 + 32 * 16 + 16 * 8));
  r.mips = 1;
  r.format = VK_FORMAT_D32_SFLOAT_S8_UINT;  // 8 bytes a texel, as gpu::format_info says
  EXPECT_EQ(estimate_memory(r).size, 8u * 64 * 32);
  r.format = VK_FORMAT_BC1_RGBA_UNORM_BLOCK;  // 8 bytes per 4x4 block
  EXPECT_EQ(estimate_memory(r).size, 8u * 16 * 8);
  r.format = VK_FORMAT_R64_SFLOAT;  // unknown to gpu/format: the widest common texel, 16 bytes
  EXPECT_EQ(estimate_memory(r).size, 16u * 64 * 32);
  EXPECT_EQ(estimate_memory(r).alignment, 65536u);
}

TEST(ExecutorTimings, OutOfOrderTimestampsAreNoTimingNotZero) {
  EXPECT_DOUBLE_EQ(*timestamp_interval_ms(1000, 3500, 1e-6), 2500e-6);  // 2500 ticks of 1 ns
  EXPECT_DOUBLE_EQ(*timestamp_interval_ms(7, 7, 1e-6), 0.0);            // equal: a real (if empty) range
  EXPECT_FALSE(timestamp_interval_ms(3500, 1000, 1e-6).has_value());    // the end before the begin
}

TEST(RenderGraphCompile, AliasedBlockTakesTheLargestSize) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  TextureHandle small = g.create_texture("small", TextureDesc::relative(VK_FORMAT_R8_UNORM, 0.5f));
  TextureHandle mid = g.create_texture("mid", kRgba16);
  TextureHandle big = g.create_texture("big", TextureDesc::relative(VK_FORMAT_R32G32B32A32_SFLOAT));
  g.add_pass(
      "p0", Queue::Compute, [&](PassBuilder& b) { small = b.write(small, Usage::StorageWrite); }, nullptr);
  g.add_pass(
      "p1", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(small, Usage::Sampled);
        mid = b.write(mid, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "p2", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(mid, Usage::Sampled);
        big = b.write(big, Usage::StorageWrite);
      },
      nullptr);
  g.add_pass(
      "p3", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(big, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  const uint32_t s = index_of(c, "small"), bg = index_of(c, "big");
  ASSERT_TRUE(c.shares_memory(s, bg));
  const MemoryBlock& block = c.memory_blocks[c.resources[s].memory_block];
  EXPECT_EQ(block.size, VkDeviceSize(160) * 90 * 16);
}

TEST(RenderGraphCompile, ImportedResourceStatesAndUnusedImports) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  // History: sampled from last frame, written this frame, left for the next one to sample.
  TextureHandle history = g.import_texture("history", kRgba16, VK_NULL_HANDLE, VK_NULL_HANDLE,
                                           ResourceState::shader_read_only(), ResourceState::shader_read_only());
  // An NVDF nobody reads this frame, handed to us in GENERAL and wanted SHADER_READ_ONLY.
  g.import_texture("nvdf", TextureDesc::absolute(VK_FORMAT_R8_UNORM, 64, 64, 16), VK_NULL_HANDLE, VK_NULL_HANDLE,
                   ResourceState::general_storage(), ResourceState::shader_read_only());
  g.add_pass(
      "accumulate", Queue::Compute, [&](PassBuilder& b) { history = b.read_write(history, Usage::StorageWrite); },
      nullptr);
  g.add_pass(
      "show", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(history, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  const Barrier* in = find_barrier(c.find_pass("accumulate")->barriers, "history");
  ASSERT_NE(in, nullptr);
  EXPECT_EQ(in->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(in->new_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_FALSE(in->discard);  // imported content is kept
  EXPECT_EQ(in->dst_access, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  // "show" left it SHADER_READ_ONLY but visible to the fragment shader only; the final state promises
  // compute readers too (next frame's initial state carries no pending write), so one more barrier.
  const Barrier* out_history = find_barrier(c.final_barriers, "history");
  ASSERT_NE(out_history, nullptr);
  EXPECT_EQ(out_history->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(out_history->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(out_history->dst_stages, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  const Barrier* nvdf = find_barrier(c.final_barriers, "nvdf");
  ASSERT_NE(nvdf, nullptr);
  EXPECT_EQ(nvdf->old_layout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(nvdf->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  EXPECT_EQ(nvdf->src_access, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

TEST(RenderGraphCompile, DumpsTextAndGraphviz) {
  RenderGraph g = chain_graph();
  g.add_pass(
      "lonely", Queue::Compute,
      [&](PassBuilder& b) {
        TextureHandle t = b.create_texture("lonely_out", kRgba16);
        b.write(t, Usage::StorageWrite);
      },
      nullptr);
  CompiledGraph c = g.compile();
  const std::string text = c.to_text();
  for (const char* s : {"pass 0 fill (compute)", "pass 3 readback", "culled lonely", "barrier c:", "(discard)",
                        "memory block 0", "UNDEFINED -> GENERAL"})
    EXPECT_NE(text.find(s), std::string::npos) << s << "\n" << text;
  const std::string dot = c.to_dot();
  EXPECT_EQ(dot.rfind("digraph render_graph {", 0), 0u);
  for (const char* s : {"fill", "blur", "composite", "readback", "lonely (culled)", "->"})
    EXPECT_NE(dot.find(s), std::string::npos) << s;

  // --dump-graph FILE: the extension picks the format; a bad path names the file.
  const cumulo::test::TempDir tmp("cumulo_graph_dump");
  const std::filesystem::path& dir = tmp.path;
  c.write_dump((dir / "frame.dot").string());
  c.write_dump((dir / "frame.txt").string());
  EXPECT_EQ(read_file_text(dir / "frame.dot"), dot);
  EXPECT_EQ(read_file_text(dir / "frame.txt"), text);
  try {
    c.write_dump((dir / "frame.txt" / "below_a_file.txt").string());  // a file is no folder
    ADD_FAILURE() << "no error for an unwritable path";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("below_a_file.txt"), std::string::npos) << e.what();
  }
}

TEST(RenderGraphCompile, HashIgnoresCallbacksAndImportedHandles) {
  auto build = [](VkExtent2D size, VkImage image) {
    RenderGraph g(size);
    TextureHandle out = g.import_texture("swapchain", TextureDesc::relative(VK_FORMAT_B8G8R8A8_UNORM), image,
                                         VK_NULL_HANDLE, ResourceState::acquired(), ResourceState::present());
    g.add_pass(
        "clear", Queue::Compute, [&](PassBuilder& b) { out = b.write(out, Usage::TransferDst); }, [](PassContext&) {});
    return g.hash();
  };
  EXPECT_EQ(build({160, 90}, VK_NULL_HANDLE), build({160, 90}, reinterpret_cast<VkImage>(uintptr_t(0x1234))));
  EXPECT_NE(build({160, 90}, VK_NULL_HANDLE), build({320, 180}, VK_NULL_HANDLE));
}

TEST(RenderGraphCompile, FilamentStyleDataPasses) {
  RenderGraph g(kSize);
  TextureHandle out = import_swapchain(g);
  struct MarchData {
    TextureHandle clouds;
  };
  const MarchData& march = g.add_pass<MarchData>(
      "march", Queue::Compute,
      [&](PassBuilder& b, MarchData& d) {
        d.clouds = b.create_texture("clouds", kRgba16);
        d.clouds = b.write(d.clouds, Usage::StorageWrite);
      },
      [](PassContext& c, const MarchData& d) {
        EXPECT_EQ(c.extent(d.clouds).width, 160u);
        EXPECT_EQ(c.layout(d.clouds), VK_IMAGE_LAYOUT_GENERAL);
      });
  g.add_pass(
      "show", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(march.clouds, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      nullptr);
  CompiledGraph c = g.compile();
  EXPECT_EQ(c.passes.size(), 2u);
  g.execute_without_device(c);
}

TEST(RenderGraphCompile, DeclarationErrorsNameThePassAndResource) {
  {
    RenderGraph g(kSize);
    TextureHandle t = g.create_texture("t", kRgba16);
    TextureHandle t1 = t;
    g.add_pass(
        "a", Queue::Compute, [&](PassBuilder& b) { t1 = b.write(t, Usage::StorageWrite); }, nullptr);
    g.add_pass(
        "b", Queue::Compute, [&](PassBuilder& b) { b.write(t, Usage::StorageWrite); }, nullptr);  // stale
    const std::string e = compile_error(g);
    EXPECT_NE(e.find("pass 'b' uses version 0 of 't' but version 1 is the latest"), std::string::npos) << e;
  }
  {
    RenderGraph g(kSize);
    TextureHandle t = g.create_texture("t", kRgba16);
    g.add_pass(
        "early", Queue::Compute, [&](PassBuilder& b) { b.read(t, Usage::Sampled); }, nullptr);
    const std::string e = compile_error(g);
    EXPECT_NE(e.find("pass 'early': reads a transient that no earlier pass wrote: 't'"), std::string::npos) << e;
  }
  {
    RenderGraph g(kSize);
    TextureHandle t = g.create_texture("t", kRgba16);
    g.add_pass(
        "cs", Queue::Compute, [&](PassBuilder& b) { b.write(t, Usage::ColorAttachment); }, nullptr);
    EXPECT_NE(compile_error(g).find("pass 'cs' is a compute pass but uses 't' as color-attachment"), std::string::npos);
  }
  {
    RenderGraph g(kSize);
    TextureHandle t = g.create_texture("t", kRgba16);
    g.add_pass(
        "w", Queue::Compute, [&](PassBuilder& b) { t = b.write(t, Usage::StorageWrite); }, nullptr);
    g.add_pass(
        "both", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(t, Usage::Sampled);
          b.write(t, Usage::StorageWrite);
        },
        nullptr);
    EXPECT_NE(compile_error(g).find("one layout per image per pass"), std::string::npos);
  }
  {
    RenderGraph g(kSize);
    g.add_pass("same", Queue::Compute, nullptr, nullptr);
    g.add_pass("same", Queue::Compute, nullptr, nullptr);
    EXPECT_NE(compile_error(g).find("two passes are named 'same'"), std::string::npos);
  }
  {
    RenderGraph g(kSize);
    BufferHandle buf = g.create_buffer("buf", {64});
    g.add_pass(
        "bad", Queue::Compute, [&](PassBuilder& b) { b.write(buf, Usage::ColorAttachment); }, nullptr);
    EXPECT_NE(compile_error(g).find("usage color-attachment does not apply to buffer 'buf'"), std::string::npos);
  }
  {
    RenderGraph g(kSize);
    g.create_texture("noformat", TextureDesc{});
    EXPECT_NE(compile_error(g).find("texture 'noformat' has no format"), std::string::npos);
  }
  {
    RenderGraph g(kSize);
    VkImage image = reinterpret_cast<VkImage>(uintptr_t(0x42));
    g.import_texture("one", kRgba16, image, VK_NULL_HANDLE, ResourceState::shader_read_only());
    g.import_texture("two", kRgba16, image, VK_NULL_HANDLE, ResourceState::shader_read_only());
    EXPECT_NE(compile_error(g).find("'one' and 'two' import the same Vulkan object"), std::string::npos);
  }
  EXPECT_THROW(RenderGraph({0, 90}), Error);
}

namespace {

// A read-only import two passes share is found again by its name and image; another image or name is not.
TEST(RenderGraphCompile, FindImportReturnsTheSameReadOnlyImport) {
  RenderGraph g(kSize);
  VkImage a = reinterpret_cast<VkImage>(uintptr_t(0x10)), b = reinterpret_cast<VkImage>(uintptr_t(0x20));
  const TextureDesc desc = TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, 8, 8);
  EXPECT_FALSE(g.find_import("maps", a).valid());
  const TextureHandle h = g.import_texture("maps", desc, a, VK_NULL_HANDLE, ResourceState::shader_read_only());
  const TextureHandle again = g.find_import("maps", a);
  ASSERT_TRUE(again.valid());
  EXPECT_EQ(again.index, h.index);
  EXPECT_FALSE(g.find_import("maps", b).valid());
  EXPECT_FALSE(g.find_import("other", a).valid());
  g.create_texture("maps (transient)", desc);
  EXPECT_FALSE(g.find_import("maps (transient)", VK_NULL_HANDLE).valid());
}

}  // namespace
