// Render-graph features the modules need, on the compiled form (no device): side-effect passes,
// persistent textures that carry their state from frame to frame, history ping-pong with its
// validity flag, and the hash that lets the executor keep several compiled shapes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/render/graph/render_graph.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

constexpr VkExtent2D kSize{160, 90};

const Barrier* find_barrier(const std::vector<Barrier>& barriers, const std::string& name) {
  for (const Barrier& b : barriers)
    if (b.name == name) return &b;
  return nullptr;
}

TextureHandle import_output(RenderGraph& g) {
  return g.import_texture("output", TextureDesc::absolute(VK_FORMAT_R8G8B8A8_UNORM, kSize.width, kSize.height),
                          VK_NULL_HANDLE, VK_NULL_HANDLE, ResourceState::undefined(), ResourceState::shader_read_only());
}

}  // namespace

TEST(RenderGraphFeatures, SideEffectPassIsNeverCulled) {
  RenderGraph g(kSize);
  auto t = g.create_texture("scratch", TextureDesc::relative(VK_FORMAT_R8_UNORM));
  int ran = 0;
  g.add_pass("unread", Queue::Compute, [&](PassBuilder& b) { t = b.write(t, Usage::StorageWrite); },
             [&](PassContext&) { ++ran; });
  auto u = g.create_texture("scratch 2", TextureDesc::relative(VK_FORMAT_R8_UNORM));
  g.add_pass("readback", Queue::Compute,
             [&](PassBuilder& b) {
               u = b.write(u, Usage::StorageWrite);
               b.side_effect();
             },
             [&](PassContext&) { ran += 10; });
  CompiledGraph c = g.compile();
  EXPECT_EQ(c.culled, std::vector<std::string>{"unread"});
  ASSERT_NE(c.find_pass("readback"), nullptr);
  EXPECT_TRUE(c.find_pass("readback")->side_effect);
  g.execute_without_device(c);
  EXPECT_EQ(ran, 10);
}

TEST(RenderGraphFeatures, PersistentTextureStartsWhereTheLastFrameLeftIt) {
  PersistentTexture grid;
  grid.name = "light grid";
  grid.desc = TextureDesc::absolute(VK_FORMAT_R8G8_UNORM, 256, 256, 32);
  uint64_t hashes[3];
  for (int frame = 0; frame < 3; ++frame) {
    RenderGraph g(kSize);
    auto out = import_output(g);
    auto lg = g.import_persistent(grid);
    g.add_pass("light grid update", Queue::Compute, [&](PassBuilder& b) { lg = b.read_write(lg, Usage::StorageWrite); },
               nullptr);
    g.add_pass("march", Queue::Graphics,
               [&](PassBuilder& b) {
                 b.read(lg, Usage::Sampled);
                 out = b.write(out, Usage::ColorAttachment);
               },
               nullptr);
    CompiledGraph c = g.compile();
    hashes[frame] = c.hash;
    const Barrier* first = find_barrier(c.find_pass("light grid update")->barriers, "light grid");
    ASSERT_NE(first, nullptr);
    if (frame == 0) {
      EXPECT_EQ(first->old_layout, VK_IMAGE_LAYOUT_UNDEFINED);  // never used: contents undefined
    } else {
      // Last frame ended with the march sampling it: the update waits for that read (WAR) and moves
      // the grid back from SHADER_READ_ONLY to GENERAL, keeping its contents.
      EXPECT_EQ(first->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      EXPECT_EQ(first->new_layout, VK_IMAGE_LAYOUT_GENERAL);
      EXPECT_TRUE(first->src_stages & VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
    }
    // No final barrier for it: the next frame's first use orders itself.
    EXPECT_EQ(find_barrier(c.final_barriers, "light grid"), nullptr);
    g.execute_without_device(c);  // stores the state of the last use
    EXPECT_EQ(grid.state.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  }
  EXPECT_NE(hashes[0], hashes[1]);  // the first frame's shape differs (undefined start) ...
  EXPECT_EQ(hashes[1], hashes[2]);  // ... then every frame has the same shape: nothing recompiles
}

TEST(RenderGraphFeatures, HistoryPingPongsWithBarriersAcrossFrames) {
  HistoryTexture history("cloud history");
  VkImage a = reinterpret_cast<VkImage>(uintptr_t(0x1000)), b = reinterpret_cast<VkImage>(uintptr_t(0x2000));
  history.set_images(TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, kSize.width, kSize.height), a, VK_NULL_HANDLE,
                     b, VK_NULL_HANDLE);
  std::vector<VkImage> written;
  std::vector<bool> valid;
  uint64_t hashes[4];
  for (int frame = 0; frame < 4; ++frame) {
    if (frame == 3) history.invalidate();  // a camera cut
    RenderGraph g(kSize);
    auto out = import_output(g);
    HistoryHandles h = g.import_history(history);
    valid.push_back(h.valid);
    g.add_pass("temporal", Queue::Compute,
               [&](PassBuilder& pb) {
                 pb.read(h.previous, Usage::Sampled);
                 h.current = pb.write(h.current, Usage::StorageWrite);
               },
               nullptr);
    written.push_back(g.imported_texture(h.current.index).image);
    g.add_pass("composite", Queue::Graphics,
               [&](PassBuilder& pb) {
                 pb.read(h.current, Usage::Sampled);
                 out = pb.write(out, Usage::ColorAttachment);
               },
               nullptr);
    CompiledGraph c = g.compile();
    hashes[frame] = c.hash;
    const CompiledPass* t = c.find_pass("temporal");
    const Barrier* prev = find_barrier(t->barriers, "cloud history (previous)");
    const Barrier* cur = find_barrier(t->barriers, "cloud history");
    ASSERT_NE(prev, nullptr);
    ASSERT_NE(cur, nullptr);
    if (frame >= 1) {
      // Last frame's target (written by 'temporal', then sampled by 'composite') is read: it is
      // already in SHADER_READ_ONLY, and the RAW on its storage write was covered last frame.
      EXPECT_EQ(prev->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      EXPECT_EQ(prev->new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    if (frame >= 2) {
      // This frame's target was last frame's 'previous' (only sampled): WAR on that read, to GENERAL.
      EXPECT_EQ(cur->old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      EXPECT_EQ(cur->new_layout, VK_IMAGE_LAYOUT_GENERAL);
      EXPECT_TRUE(cur->src_stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    }
    g.execute_without_device(c);
  }
  EXPECT_EQ(valid, (std::vector<bool>{false, true, true, false}));
  ASSERT_EQ(written.size(), 4u);
  EXPECT_NE(written[0], written[1]);  // ping-pong
  EXPECT_EQ(written[0], written[2]);
  EXPECT_EQ(hashes[2], hashes[3]);  // steady state: one shape (the cut changes the flag, not the shape)
}

TEST(RenderGraphFeatures, HistoryWithoutImagesAndRelativePersistentAreRefused) {
  RenderGraph g(kSize);
  HistoryTexture h("h");
  EXPECT_THROW(g.import_history(h), Error);
  PersistentTexture p;
  p.name = "p";
  p.desc = TextureDesc::relative(VK_FORMAT_R8_UNORM);
  EXPECT_THROW(g.import_persistent(p), Error);
}

TEST(RenderGraphFeatures, ShapesDifferOnlyWhereTheFrameDiffers) {
  auto build = [](bool lightning) {
    RenderGraph g(kSize);
    auto out = import_output(g);
    auto hdr = g.create_texture("hdr", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT));
    g.add_pass("clouds", Queue::Compute, [&](PassBuilder& b) { hdr = b.write(hdr, Usage::StorageWrite); }, nullptr);
    if (lightning)
      g.add_pass("lightning", Queue::Compute, [&](PassBuilder& b) { hdr = b.read_write(hdr, Usage::StorageWrite); },
                 nullptr);
    g.add_pass("tonemap", Queue::Graphics,
               [&](PassBuilder& b) {
                 b.read(hdr, Usage::Sampled);
                 out = b.write(out, Usage::ColorAttachment);
               },
               nullptr);
    return g.hash();
  };
  EXPECT_EQ(build(false), build(false));
  EXPECT_NE(build(false), build(true));
  EXPECT_EQ(build(true), build(true));
}
