// RenderGraph::compile(), last step: derive every barrier and layout transition (synchronization2).
//
// Per resource we follow its accesses through the live passes and keep what the next access must
// wait for:
// - a layout change (any image whose layout differs) is a read-write of the image: it waits for
//   every earlier read and write (src = last write + reads since), and makes the image visible to
//   the new access;
// - a write (WAW, WAR) waits for the last write (made available) and for the reads since it
//   (execution dependency only: a read leaves nothing to flush);
// - a read after a write (RAW) needs the write made available and visible to the reading stage;
//   a later read in a stage/access already made visible needs nothing (read-after-read);
// - imported resources start from their declared initial state and end in their final state
//   (one more batch after the last pass); persistent ones start from the state the previous frame
//   left them in and have no final barrier (their next first use waits for this frame's last use);
// - a transient's first use in a frame discards (old layout UNDEFINED) and waits for whatever last
//   used its memory: the previous occupant of its aliased block or, for the first occupant, the
//   block's last occupant in the previous frame (frames are recorded in order on one queue).
// All barriers of one pass go into one vkCmdPipelineBarrier2, recorded before the pass.
#include "engine/core/error.h"
#include "engine/render/graph/detail/compiler.h"

namespace cumulo::render::detail {
namespace {

struct Track {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 write_stages = 0;    // the last write (or layout transition)
  VkAccessFlags2 write_access = 0;           // its accesses still to be made available
  VkPipelineStageFlags2 read_stages = 0;     // reads since that write
  VkPipelineStageFlags2 visible_stages = 0;  // where the last write is already visible
  VkAccessFlags2 visible_access = 0;
};

// Whatever touched the resource (or its memory) before: treated as a write in `stages` that may
// also have read there (the conservative reading of an outside state).
Track track_from(VkImageLayout layout, VkPipelineStageFlags2 stages, VkAccessFlags2 access) {
  Track t;
  t.layout = layout;
  t.write_stages = stages;
  t.write_access = access & kWriteAccessMask;
  t.read_stages = stages;
  return t;
}

// Applies one access to `t`; returns true and fills `b` when a barrier is needed before it.
bool apply(Track& t, bool image, VkPipelineStageFlags2 stages, VkAccessFlags2 access, VkImageLayout layout, bool writes,
           Barrier& b) {
  const bool layout_change = image && layout != t.layout;
  b.old_layout = image ? t.layout : VK_IMAGE_LAYOUT_UNDEFINED;
  b.new_layout = image ? layout : VK_IMAGE_LAYOUT_UNDEFINED;
  b.dst_stages = stages;
  b.dst_access = access;
  if (layout_change || writes) {
    b.src_stages = t.write_stages | t.read_stages;
    b.src_access = t.write_access;
    const bool needed = layout_change || b.src_stages != 0;
    t.layout = image ? layout : t.layout;
    t.write_stages = stages;
    // A write leaves its accesses to flush; a transition alone leaves none, but later accesses in
    // other stages must still be ordered after it (hence write_stages = stages).
    t.write_access = writes ? (access & kWriteAccessMask) : 0;
    t.read_stages = writes ? 0 : stages;
    t.visible_stages = writes ? 0 : stages;
    t.visible_access = writes ? 0 : access;
    return needed;
  }
  // Read in the current layout.
  const bool covered = (stages & ~t.visible_stages) == 0 && (access & ~t.visible_access) == 0;
  t.read_stages |= stages;
  if (t.write_stages == 0 || covered) return false;
  b.src_stages = t.write_stages;
  b.src_access = t.write_access;
  t.visible_stages |= stages;
  t.visible_access |= access;
  return true;
}

}  // namespace

void Compiler::derive_barriers() {
  const auto& passes = out_.passes;
  auto last_access = [&](uint32_t r) -> const ResourceAccess& {
    for (const ResourceAccess& a : passes[out_.resources[r].last_pass].accesses)
      if (a.resource == r) return a;
    fail("render graph: internal: '%s' missing from its last pass", out_.resources[r].name.c_str());
  };
  // Who used a transient's memory before its first use: the previous occupant of its block, the
  // block's last occupant for the first one, itself for a resource with its own memory.
  auto memory_predecessor = [&](uint32_t r) -> uint32_t {
    const int block = out_.resources[r].memory_block;
    if (block < 0) return r;
    const auto& occupants = out_.memory_blocks[block].resources;
    for (size_t i = 0; i < occupants.size(); ++i)
      if (occupants[i] == r) return occupants[(i + occupants.size() - 1) % occupants.size()];
    return r;
  };

  std::vector<Track> tracks(out_.resources.size());
  std::vector<bool> started(out_.resources.size(), false);
  for (CompiledPass& pass : out_.passes) {
    for (const ResourceAccess& a : pass.accesses) {
      const CompiledResource& r = out_.resources[a.resource];
      Track& t = tracks[a.resource];
      bool discard = false;
      if (!started[a.resource]) {
        started[a.resource] = true;
        if (r.imported) {
          t = track_from(r.initial.layout, r.initial.stages, r.initial.access);
        } else {
          const ResourceAccess& prev = last_access(memory_predecessor(a.resource));
          t = track_from(VK_IMAGE_LAYOUT_UNDEFINED, prev.stages, prev.access);
          discard = true;
        }
      }
      Barrier b;
      b.resource = a.resource;
      b.name = r.name;
      b.image = r.image;
      b.discard = discard;
      if (apply(t, r.image, a.stages, a.access, a.layout, a.write, b) || discard) pass.barriers.push_back(b);
    }
  }

  // Imported resources to their final state (also the ones no live pass touched).
  for (uint32_t i = 0; i < out_.resources.size(); ++i) {
    const CompiledResource& r = out_.resources[i];
    if (!r.imported || r.persistent) continue;  // persistent: the next frame starts from the last use
    Track& t = tracks[i];
    if (!started[i]) t = track_from(r.initial.layout, r.initial.stages, r.initial.access);
    // final.layout UNDEFINED means "any layout": keep the current one.
    const VkImageLayout wanted = (r.image && r.final.layout != VK_IMAGE_LAYOUT_UNDEFINED) ? r.final.layout : t.layout;
    Barrier b;
    b.resource = i;
    b.name = r.name;
    b.image = r.image;
    const bool final_writes = (r.final.access & kWriteAccessMask) != 0;
    bool needed = apply(t, r.image, r.final.stages, r.final.access, wanted, final_writes, b);
    // Make the last write available even when the next user is unknown to us (present, host).
    if (!needed && b.src_access == 0 && t.write_access != 0) {
      b.src_stages = t.write_stages;
      b.src_access = t.write_access;
      needed = true;
    }
    if (!started[i] && !(r.image && r.initial.layout != wanted)) needed = false;  // untouched: nothing to do
    if (needed) out_.final_barriers.push_back(b);
  }
}

}  // namespace cumulo::render::detail
