// Randomized render graphs, no device: whatever the declaration, the compiled graph keeps its
// invariants (layout continuity, every hazard covered by a barrier, aliasing only of disjoint
// lifetimes, culled passes never run).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "engine/render/graph/render_graph.h"

using namespace cumulo::render;

namespace {

struct Use {
  int pass;  // position in the compiled order
  ResourceAccess access;
};

// Every use of `resource` in execution order.
std::vector<Use> uses_of(const CompiledGraph& c, uint32_t resource) {
  std::vector<Use> out;
  for (int p = 0; p < int(c.passes.size()); ++p)
    for (const ResourceAccess& a : c.passes[p].accesses)
      if (a.resource == resource) out.push_back({p, a});
  return out;
}

const Barrier* barrier_in(const CompiledGraph& c, int pass, uint32_t resource) {
  for (const Barrier& b : c.passes[pass].barriers)
    if (b.resource == resource) return &b;
  return nullptr;
}

constexpr VkAccessFlags2 kWrites = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT;

RenderGraph random_graph(std::mt19937& rng, std::vector<std::string>& ran) {
  RenderGraph g({64, 32});
  auto pick = [&](int n) { return int(rng() % uint32_t(n)); };
  TextureHandle out = g.import_texture("out", TextureDesc::relative(VK_FORMAT_R8G8B8A8_UNORM), VK_NULL_HANDLE,
                                       VK_NULL_HANDLE, ResourceState::acquired(), ResourceState::present());
  std::vector<TextureHandle> textures;
  std::vector<bool> written;
  const int resource_count = 3 + pick(6);
  for (int i = 0; i < resource_count; ++i) {
    textures.push_back(g.create_texture("t" + std::to_string(i),
                                        TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT, pick(2) ? 1.0f : 0.5f)));
    written.push_back(false);
  }
  const Usage reads[] = {Usage::Sampled, Usage::StorageRead, Usage::TransferSrc};
  const Usage writes[] = {Usage::StorageWrite, Usage::ColorAttachment, Usage::TransferDst};
  const int pass_count = 2 + pick(10);
  for (int p = 0; p < pass_count; ++p) {
    const bool last = p + 1 == pass_count;
    const Queue queue = pick(2) ? Queue::Compute : Queue::Graphics;
    const std::string name = "p" + std::to_string(p);
    g.add_pass(
        name, last ? Queue::Graphics : queue,
        [&](PassBuilder& b) {
          std::vector<int> used;
          for (int k = pick(3); k > 0; --k) {  // reads of written resources
            int r = pick(resource_count);
            if (!written[r] || std::find(used.begin(), used.end(), r) != used.end()) continue;
            used.push_back(r);
            b.read(textures[r], reads[pick(3)]);
          }
          for (int k = 1 + pick(2); k > 0; --k) {  // writes
            int r = pick(resource_count);
            if (std::find(used.begin(), used.end(), r) != used.end()) continue;
            used.push_back(r);
            Usage u = writes[pick(3)];
            if (u == Usage::ColorAttachment && (last ? false : queue == Queue::Compute)) u = Usage::StorageWrite;
            textures[r] = b.write(textures[r], u);
            written[r] = true;
          }
          if (last) out = b.write(out, Usage::ColorAttachment);
        },
        [&ran, name](PassContext&) { ran.push_back(name); });
  }
  return g;
}

}  // namespace

TEST(RenderGraphRandom, InvariantsHoldForRandomGraphs) {
  std::mt19937 rng(1234);
  for (int iteration = 0; iteration < 500; ++iteration) {
    std::vector<std::string> ran;
    RenderGraph g = random_graph(rng, ran);
    CompiledGraph c = g.compile();
    SCOPED_TRACE(c.to_text());

    // Culled passes never run; live ones run in order.
    g.execute_without_device(c);
    ASSERT_EQ(ran.size(), c.passes.size());
    for (size_t i = 0; i < ran.size(); ++i) EXPECT_EQ(ran[i], c.passes[i].name);

    for (uint32_t r = 0; r < c.resources.size(); ++r) {
      const CompiledResource& res = c.resources[r];
      const std::vector<Use> uses = uses_of(c, r);
      if (uses.empty()) continue;
      // Layout continuity: each use finds the image in the layout it declared; a transient's first
      // use discards.
      VkImageLayout layout = res.imported ? res.initial.layout : VK_IMAGE_LAYOUT_UNDEFINED;
      for (size_t u = 0; u < uses.size(); ++u) {
        const Barrier* b = barrier_in(c, uses[u].pass, r);
        if (b) {
          EXPECT_EQ(b->old_layout, layout) << res.name;
          layout = b->new_layout;
        }
        EXPECT_EQ(layout, uses[u].access.layout) << res.name << " in " << c.passes[uses[u].pass].name;
        if (u == 0 && !res.imported) {
          ASSERT_NE(b, nullptr);
          EXPECT_TRUE(b->discard);
        }
      }
      // Hazards: every access after a write (RAW, WAW) has a barrier in between that makes the
      // write available; every write after reads (WAR) waits for those readers' stages.
      for (size_t u = 1; u < uses.size(); ++u) {
        for (size_t w = u; w-- > 0;) {
          const Use& prev = uses[w];
          if (!(prev.access.access & kWrites) && !(uses[u].access.access & kWrites)) continue;
          bool covered = false;
          for (int p = prev.pass + 1; p <= uses[u].pass && !covered; ++p) {
            const Barrier* b = barrier_in(c, p, r);
            covered = b && (b->src_stages & prev.access.stages) == prev.access.stages &&
                      (b->src_access & prev.access.access & kWrites) == (prev.access.access & kWrites);
          }
          EXPECT_TRUE(covered) << res.name << ": " << c.passes[prev.pass].name << " -> " << c.passes[uses[u].pass].name;
          if (prev.access.access & kWrites) break;  // earlier uses are ordered through this write
        }
      }
    }
    // Aliasing: occupants of a block never live at the same time, and never imported.
    for (const MemoryBlock& block : c.memory_blocks)
      for (size_t i = 0; i < block.resources.size(); ++i)
        for (size_t j = 0; j < i; ++j) {
          const CompiledResource &a = c.resources[block.resources[i]], &b = c.resources[block.resources[j]];
          EXPECT_FALSE(a.imported || b.imported);
          EXPECT_TRUE(a.last_pass < b.first_pass || b.last_pass < a.first_pass) << a.name << " / " << b.name;
        }
    if (HasFailure()) break;  // one failing graph is enough to read
  }
}
