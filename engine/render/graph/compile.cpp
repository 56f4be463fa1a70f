// RenderGraph::compile(): the steps before barriers (validate .. assign_memory). barriers.cpp has
// the last step. Each step reads what the previous ones produced in the Compiler's members.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "engine/core/error.h"
#include "engine/render/graph/detail/compiler.h"

namespace cumulo::render::detail {

void Compiler::fail_pass(uint32_t pass, const char* what, uint32_t resource) const {
  fail("render graph: pass '%s': %s '%s'", passes_[pass].name.c_str(), what, resources_[resource].name.c_str());
}

// ---- validate: every declaration error, named by pass and resource ----------------------------
void Compiler::validate() {
  std::set<std::string> names;
  for (const auto& r : resources_) {
    if (r.name.empty()) fail("render graph: a resource has an empty name");
    if (!names.insert(r.name).second) fail("render graph: two resources are named '%s'", r.name.c_str());
    if (r.image) {
      const TextureDesc& t = r.texture;
      if (t.format == VK_FORMAT_UNDEFINED) fail("render graph: texture '%s' has no format", r.name.c_str());
      if (t.width == 0 && !(t.size_scale > 0.0f))
        fail("render graph: texture '%s' has size_scale %g (must be > 0)", r.name.c_str(), double(t.size_scale));
      if (t.width > 0 && t.height == 0) fail("render graph: texture '%s' has width but no height", r.name.c_str());
      if (t.mips == 0 || t.depth == 0) fail("render graph: texture '%s' has 0 mips or 0 depth", r.name.c_str());
      if (t.type == ImageType::Image2D && t.depth != 1)
        fail("render graph: 2D texture '%s' has depth %u (use ImageType::Image3D)", r.name.c_str(), t.depth);
    } else if (r.buffer.size == 0) {
      fail("render graph: buffer '%s' has size 0", r.name.c_str());
    }
  }
  // One Vulkan object imported twice would get two independent barrier chains.
  for (size_t i = 0; i < resources_.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      const ResourceDecl &a = resources_[i], &b = resources_[j];
      const bool same_image = a.image && b.image && a.vk_image && a.vk_image == b.vk_image;
      const bool same_buffer = !a.image && !b.image && a.vk_buffer && a.vk_buffer == b.vk_buffer;
      if (a.imported && b.imported && (same_image || same_buffer))
        fail("render graph: '%s' and '%s' import the same Vulkan object", b.name.c_str(), a.name.c_str());
    }
  std::set<std::string> pass_names;
  std::vector<uint32_t> version(resources_.size(), 0);
  for (uint32_t p = 0; p < passes_.size(); ++p) {
    const PassDecl& pass = passes_[p];
    if (pass.name.empty()) fail("render graph: a pass has an empty name");
    // Unique: timings and dumps are keyed by pass name.
    if (!pass_names.insert(pass.name).second) fail("render graph: two passes are named '%s'", pass.name.c_str());
    for (const AccessDecl& a : pass.accesses) {
      const ResourceDecl& r = resources_[a.resource];
      const UsageInfo u = usage_info(a.usage, pass.queue, a.stages);
      if (r.image ? !u.images : !u.buffers)
        fail("render graph: pass '%s': usage %s does not apply to %s '%s'", pass.name.c_str(), usage_name(a.usage),
             r.image ? "texture" : "buffer", r.name.c_str());
      if (u.graphics_only && pass.queue == Queue::Compute)
        fail("render graph: pass '%s' is a compute pass but uses '%s' as %s", pass.name.c_str(), r.name.c_str(),
             usage_name(a.usage));
      if (a.read && a.write && !(u.can_write && u.read_access))
        fail("render graph: pass '%s': usage %s cannot read_write '%s'", pass.name.c_str(), usage_name(a.usage),
             r.name.c_str());
      if (a.read && !a.write && !u.can_read)
        fail("render graph: pass '%s': usage %s is not a read of '%s'%s", pass.name.c_str(), usage_name(a.usage),
             r.name.c_str(), u.can_write ? " (use write or read_write)" : "");
      if (a.write && !a.read && !u.can_write)
        fail("render graph: pass '%s': usage %s is not a write of '%s'", pass.name.c_str(), usage_name(a.usage),
             r.name.c_str());
      if (a.version != version[a.resource])
        fail(
            "render graph: pass '%s' uses version %u of '%s' but version %u is the latest (a write returns the next "
            "version; use the handle it returned)",
            pass.name.c_str(), a.version, r.name.c_str(), version[a.resource]);
      if (a.read && !r.imported && version[a.resource] == 0)
        fail_pass(p, "reads a transient that no earlier pass wrote:", a.resource);
      if (a.write) ++version[a.resource];
    }
  }
}

// ---- merge_accesses: one access per (pass, resource) ------------------------------------------
void Compiler::merge_accesses() {
  accesses_.assign(passes_.size(), {});
  for (uint32_t p = 0; p < passes_.size(); ++p) {
    auto& merged = accesses_[p];
    for (const AccessDecl& a : passes_[p].accesses) {
      const UsageInfo u = usage_info(a.usage, passes_[p].queue, a.stages);
      VkAccessFlags2 access = (a.read ? u.read_access : 0) | (a.write ? u.write_access : 0);
      // A depth test reads the depth it may overwrite.
      if (a.usage == Usage::DepthWrite) access |= u.read_access;
      auto it =
          std::find_if(merged.begin(), merged.end(), [&](const ResourceAccess& m) { return m.resource == a.resource; });
      if (it == merged.end()) {
        merged.push_back({a.resource, a.usage, a.read, a.write, u.stages, access, u.layout});
        continue;
      }
      if (resources_[a.resource].image && it->layout != u.layout)
        fail("render graph: pass '%s' uses image '%s' as both %s and %s: one layout per image per pass",
             passes_[p].name.c_str(), resources_[a.resource].name.c_str(), usage_name(it->usage), usage_name(a.usage));
      it->read |= a.read;
      it->write |= a.write;
      if (a.write) it->usage = a.usage;
      it->stages |= u.stages;
      it->access |= access;
    }
  }
}

// ---- describe_resources: resolve sizes against the output ---------------------------------------
void Compiler::describe_resources() {
  out_.output_size = output_size_;
  out_.resources.resize(resources_.size());
  for (size_t i = 0; i < resources_.size(); ++i) {
    const ResourceDecl& d = resources_[i];
    CompiledResource& r = out_.resources[i];
    r.name = d.name;
    r.image = d.image;
    r.imported = d.imported;
    r.size = d.buffer.size;
    r.initial = d.initial;
    r.final = d.final;
    r.persistent = d.persistent != nullptr;
    if (!d.image) continue;
    const TextureDesc& t = d.texture;
    r.format = t.format;
    r.type = t.type;
    r.mips = t.mips;
    if (t.width > 0) {
      r.extent = {t.width, t.height, t.depth};
    } else {
      const VkExtent2D e = relative_extent(output_size_, t.size_scale);
      r.extent = {e.width, e.height, t.depth};
    }
  }
}

// ---- cull: walk back from the outputs ----------------------------------------------------------
// Outputs are the imported resources: whatever a pass writes into them outlives the graph. A pass is
// live when it has a side effect or a version it writes is needed; the versions a live pass reads become needed. Walking the
// passes backwards visits every consumer before its producer, so one sweep suffices.
void Compiler::cull() {
  std::set<std::pair<uint32_t, uint32_t>> needed;  // (resource, version)
  std::vector<uint32_t> latest(resources_.size(), 0);
  for (const auto& p : passes_)
    for (const auto& a : p.accesses)
      if (a.write) latest[a.resource] = a.version + 1;
  for (uint32_t r = 0; r < resources_.size(); ++r)
    if (resources_[r].imported && latest[r] > 0) needed.insert({r, latest[r]});

  live_.assign(passes_.size(), false);
  for (uint32_t p = uint32_t(passes_.size()); p-- > 0;) {
    live_[p] = passes_[p].side_effect;
    for (const AccessDecl& a : passes_[p].accesses)
      if (a.write && needed.count({a.resource, a.version + 1})) live_[p] = true;
    if (!live_[p]) continue;
    for (const AccessDecl& a : passes_[p].accesses)
      if (a.read) needed.insert({a.resource, a.version});
  }
  for (uint32_t p = 0; p < passes_.size(); ++p)
    if (!live_[p]) out_.culled.push_back(passes_[p].name);
}

// ---- order: execution order of the live passes ---------------------------------------------------
// Declaration order is already a valid topological order (a handle version exists only after the
// pass that writes it was declared, and validate() rejects stale versions), so it is kept, as in
// Filament. Every pass records into one command buffer on one queue; reordering to spread
// dependent passes apart (Granite) would only help a GPU that overlaps passes, and is left out.
void Compiler::order() {
  for (uint32_t p = 0; p < passes_.size(); ++p) {
    if (!live_[p]) continue;
    order_.push_back(p);
    CompiledPass cp;
    cp.declared = p;
    cp.name = passes_[p].name;
    cp.queue = passes_[p].queue;
    cp.side_effect = passes_[p].side_effect;
    cp.accesses = accesses_[p];
    out_.passes.push_back(std::move(cp));
  }
}

// ---- compute_lifetimes: first and last use, creation usage flags ---------------------------------
void Compiler::compute_lifetimes() {
  for (int pos = 0; pos < int(out_.passes.size()); ++pos) {
    for (const ResourceAccess& a : out_.passes[pos].accesses) {
      CompiledResource& r = out_.resources[a.resource];
      if (r.first_pass < 0) r.first_pass = pos;
      r.last_pass = pos;
      const UsageInfo u = usage_info(a.usage, out_.passes[pos].queue, 0);
      r.image_usage |= u.image_usage;
      r.buffer_usage |= u.buffer_usage;
    }
  }
}

// ---- assign_memory: alias transient images ---------------------------------------------------------
// Two resources may share one memory block when ALL of these hold (Granite keeps the same rules):
// 1. both are images: buffers are excluded because ours are small (parameters, indirect args,
//    readback) and aliasing them would save little while making every buffer barrier a discard;
// 2. both are transient: imported resources (swapchain, history, light grid, NVDFs) own their
//    memory, and a history resource must keep its content into the next frame, so it is imported;
// 3. their lifetimes [first_pass, last_pass] do not overlap in the execution order;
// 4. their memory types are compatible (memoryTypeBits intersect); the block takes the max size and
//    alignment and the AND of the type bits;
// 5. same queue: every pass records into one command buffer on one queue, so the barrier at the
//    next occupant's first use orders it after the previous occupant's last use. With async
//    compute, a cross-queue handover would need a semaphore, not a barrier: such transients must
//    then be excluded here;
// 6. no resource aliases itself across frames: a transient never carries content from one frame
//    to the next (its first use in every frame is a discard, old layout UNDEFINED, ordered after
//    the block's last use in the previous frame; see derive_barriers).
void Compiler::assign_memory() {
  MemoryQueryFn query = options_.memory_query ? options_.memory_query : MemoryQueryFn(estimate_memory);
  std::vector<uint32_t> images;
  for (uint32_t i = 0; i < out_.resources.size(); ++i) {
    const CompiledResource& r = out_.resources[i];
    if (r.image && !r.imported && r.first_pass >= 0) images.push_back(i);
  }
  std::stable_sort(images.begin(), images.end(),
                   [&](uint32_t a, uint32_t b) { return out_.resources[a].first_pass < out_.resources[b].first_pass; });

  std::vector<int> block_last_use;  // per block: the last pass position of its occupants
  for (uint32_t i : images) {
    CompiledResource& r = out_.resources[i];
    const MemoryQuery need = query(r);
    int best = -1;
    if (options_.alias_memory) {
      for (int b = 0; b < int(out_.memory_blocks.size()); ++b) {
        const MemoryBlock& block = out_.memory_blocks[b];
        if (block_last_use[b] >= r.first_pass) continue;                      // rule 3
        if ((block.memory_type_bits & need.memory_type_bits) == 0) continue;  // rule 4
        // Best fit: the smallest block that is large enough; else the largest (it grows least).
        auto fits = [&](int x) { return out_.memory_blocks[x].size >= need.size; };
        if (best < 0 || (fits(b) && (!fits(best) || block.size < out_.memory_blocks[best].size)) ||
            (!fits(b) && !fits(best) && block.size > out_.memory_blocks[best].size))
          best = b;
      }
    }
    if (best < 0) {
      out_.memory_blocks.push_back({need.size, need.alignment, need.memory_type_bits, {}});
      block_last_use.push_back(-1);
      best = int(out_.memory_blocks.size() - 1);
    }
    MemoryBlock& block = out_.memory_blocks[best];
    block.size = std::max(block.size, need.size);
    block.alignment = std::max(block.alignment, need.alignment);
    block.memory_type_bits &= need.memory_type_bits;
    block.resources.push_back(i);
    block_last_use[best] = r.last_pass;
    r.memory_block = best;
  }
}

}  // namespace cumulo::render::detail
