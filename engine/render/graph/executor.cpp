// Executor: physical resources (cached by graph hash), barriers, labels, timestamps, recording.
#include "engine/render/graph/executor.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/format.h"
#include "engine/gpu/image.h"
#include "engine/render/graph/detail/graph_data.h"

namespace cumulo::render {

// The transient objects of one memory layout, shared by every shape with that layout.
struct Executor::Physical {
  uint64_t key = 0;
  uint32_t serial = 0;                  // layouts_created_ when made: tells a shape its bound layout was replaced
  uint64_t last_used = 0;               // frame counter of its last execute (least recently used is evicted)
  std::vector<gpu::Allocation> blocks;  // by memory block; declared before images: destroyed after them
  std::unordered_map<std::string, gpu::Image> images;  // transient images by name
  std::unordered_map<std::string, gpu::Buffer> buffers;  // transient buffers by name
  gpu::Context* ctx = nullptr;

  ~Physical() {
    images.clear();  // images first: they are bound to the blocks
    buffers.clear();
    for (gpu::Allocation& a : blocks) ctx->allocator().free(a);
  }
};

// One compiled graph (CPU data) and the layout its transients need.
struct Executor::Shape {
  uint64_t hash = 0;
  uint64_t layout = 0;
  uint64_t last_used = 0;
  CompiledGraph compiled;
  // Its transients in its layout's objects, by resource index (null: imported or unused), looked up by name once
  // per layout it is bound to (`bound`: that layout's serial; 0: none), not every frame.
  uint32_t bound = 0;
  std::vector<gpu::Image*> images;
  std::vector<gpu::Buffer*> buffers;
};

namespace {

gpu::ImageDesc image_desc(const CompiledResource& r) {
  gpu::ImageDesc d;
  d.type = r.type == ImageType::Image3D ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  d.format = r.format;
  d.extent = r.extent;
  d.mips = r.mips;
  d.usage = r.image_usage;
  d.name = r.name.c_str();
  return d;
}

uint64_t image_desc_key(const CompiledResource& r) {
  uint64_t h = hash64(&r.type, sizeof r.type);
  h = hash64(&r.format, sizeof r.format, h);
  h = hash64(&r.extent, sizeof r.extent, h);
  h = hash64(&r.mips, sizeof r.mips, h);
  return hash64(&r.image_usage, sizeof r.image_usage, h);
}

const ResourceAccess& last_access(const CompiledGraph& c, uint32_t r) {
  for (const ResourceAccess& a : c.passes[size_t(c.resources[r].last_pass)].accesses)
    if (a.resource == r) return a;
  fail("render graph: internal: '%s' missing from its last pass", c.resources[r].name.c_str());
}

// What the transient objects and the barriers between frames depend on: each block's size, alignment,
// memory types and occupants in order, every live transient's name and description, and its last use
// (what the next frame's first use of its memory waits for).
uint64_t layout_key(const CompiledGraph& c) {
  uint64_t h = 0x6c61796f7574ull;
  auto mix = [&h](const void* p, size_t n) { h = hash64(p, n, h); };
  auto mix_resource = [&](uint32_t i) {
    const CompiledResource& r = c.resources[i];
    h = hash64(r.name, h);
    mix(&r.image, sizeof r.image);
    if (r.image) {
      const uint64_t d = image_desc_key(r);
      mix(&d, sizeof d);
    } else {
      mix(&r.size, sizeof r.size);
      mix(&r.buffer_usage, sizeof r.buffer_usage);
    }
    const ResourceAccess& a = last_access(c, i);
    mix(&a.stages, sizeof a.stages);
    mix(&a.access, sizeof a.access);
    mix(&a.layout, sizeof a.layout);
  };
  for (const MemoryBlock& b : c.memory_blocks) {
    mix(&b.size, sizeof b.size);
    mix(&b.alignment, sizeof b.alignment);
    mix(&b.memory_type_bits, sizeof b.memory_type_bits);
    const uint32_t n = uint32_t(b.resources.size());
    mix(&n, sizeof n);
    for (uint32_t r : b.resources) mix_resource(r);
  }
  for (uint32_t i = 0; i < c.resources.size(); ++i) {  // resources with memory of their own (buffers)
    const CompiledResource& r = c.resources[i];
    if (!r.imported && r.first_pass >= 0 && r.memory_block < 0) mix_resource(i);
  }
  return h;
}

}  // namespace

Executor::Executor(gpu::Context& ctx) : ctx_(ctx) {}

Executor::~Executor() {
  shape_ = nullptr;
  physical_ = nullptr;
  layouts_.clear();
  shapes_.clear();
  for (VkQueryPool& pool : pools_)
    if (pool) vkDestroyQueryPool(ctx_.device(), pool, nullptr);
}

const CompiledGraph& Executor::compiled() const {
  if (!shape_) fail("render graph executor: nothing executed yet");
  return shape_->compiled;
}

size_t Executor::shape_count() const { return shapes_.size(); }
size_t Executor::layout_count() const { return layouts_.size(); }
size_t Executor::transient_image_count() const {
  size_t n = 0;
  for (const auto& layout : layouts_) n += layout->images.size();
  return n;
}

const PhysicalTexture& Executor::texture(uint32_t resource) const { return textures_.at(resource); }

VkDeviceSize Executor::transient_bytes() const {
  VkDeviceSize total = 0;
  for (const auto& layout : layouts_) {
    for (const gpu::Allocation& a : layout->blocks) total += a.size;
    for (const auto& [name, b] : layout->buffers) total += b.allocation().size;
  }
  return total;
}

// What the device needs for a transient image: asked once per description (an image created unbound).
VkMemoryRequirements Executor::image_requirements(const CompiledResource& r) {
  const uint64_t key = image_desc_key(r);
  auto it = requirements_.find(key);
  if (it != requirements_.end()) return it->second;
  const VkMemoryRequirements req = gpu::Image::create_unbound(ctx_, image_desc(r)).memory_requirements();
  return requirements_.emplace(key, req).first->second;
}

// Compiles against the device's real memory requirements, so that aliasing decisions use real sizes,
// alignments and memory types (CPU work only: the objects come from physical_for). A bad declaration
// throws before anything changes.
Executor::Shape& Executor::compile_shape(const RenderGraph& graph) {
  CompileOptions options;
  options.memory_query = [&](const CompiledResource& r) {
    const VkMemoryRequirements req = image_requirements(r);
    return MemoryQuery{req.size, req.alignment, req.memoryTypeBits};
  };
  auto shape = std::make_unique<Shape>();
  shape->hash = graph.hash();
  shape->compiled = graph.compile(options);
  shape->layout = layout_key(shape->compiled);
  ++compile_count_;
  if (shapes_.size() >= kMaxShapes) {  // CPU data: nothing on the device refers to it
    auto lru = std::min_element(shapes_.begin(), shapes_.end(),
                                [](const auto& a, const auto& b) { return a->last_used < b->last_used; });
    shapes_.erase(lru);
  }

  // Timestamps: two per pass, in pools that rotate over frames.
  const uint32_t queries = uint32_t(2 * shape->compiled.passes.size());
  if (ctx_.info().timestamps && queries > pool_capacity_) {
    ctx_.wait_idle();
    for (VkQueryPool& pool : pools_) {
      if (pool) vkDestroyQueryPool(ctx_.device(), pool, nullptr);
      VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
      info.queryType = VK_QUERY_TYPE_TIMESTAMP;
      info.queryCount = queries;
      VK_CHECK(vkCreateQueryPool(ctx_.device(), &info, nullptr, &pool));
      ctx_.set_name(pool, "graph timestamps");
    }
    pool_capacity_ = queries;
    for (uint32_t s = 0; s < kTimestampSlots; ++s) slot_frame_[s] = 0, slot_passes_[s].clear();
  }
  shapes_.push_back(std::move(shape));
  return *shapes_.back();
}

// The transient objects of the shape's layout: the cached ones, or new ones (one allocation per memory
// block, every occupant bound at its start).
Executor::Physical& Executor::physical_for(const Shape& shape) {
  auto found = std::find_if(layouts_.begin(), layouts_.end(), [&](const auto& p) { return p->key == shape.layout; });
  if (found != layouts_.end()) return **found;
  if (layouts_.size() >= kMaxLayouts) {
    // Evicting is the only time transient objects are freed: frames in flight may still use them.
    auto lru = std::min_element(layouts_.begin(), layouts_.end(),
                                [](const auto& a, const auto& b) { return a->last_used < b->last_used; });
    LOG_DEBUG("render graph: %zu layouts cached, evicting the least recently used", layouts_.size());
    ctx_.wait_idle();
    if (lru->get() == physical_) physical_ = nullptr;
    layouts_.erase(lru);
  }
  const CompiledGraph& c = shape.compiled;
  auto phys = std::make_unique<Physical>();
  phys->ctx = &ctx_;
  phys->key = shape.layout;
  for (size_t b = 0; b < c.memory_blocks.size(); ++b) {
    const MemoryBlock& block = c.memory_blocks[b];
    VkMemoryRequirements req{block.size, block.alignment, block.memory_type_bits};
    std::string name = strf("graph block %zu", b);
    for (uint32_t r : block.resources) name += " " + c.resources[r].name;
    phys->blocks.push_back(ctx_.allocator().allocate(req, gpu::MemoryUsage::GpuOnly, name.c_str()));
    ++blocks_created_;
    for (uint32_t r : block.resources) {
      const CompiledResource& res = c.resources[r];
      gpu::Image image = gpu::Image::create_unbound(ctx_, image_desc(res));
      ++images_created_;
      image.bind_memory(phys->blocks.back());
      const std::string label = "graph:" + res.name;
      ctx_.set_name(image.handle(), label);
      ctx_.set_name(image.view(), label);
      // Single-mip views for passes that build a mip chain (PassContext::mip_view); storage-capable only.
      if (res.mips > 1)
        for (uint32_t m = 0; m < res.mips; ++m) image.mip_view(m);
      phys->images.emplace(res.name, std::move(image));
    }
  }
  for (uint32_t i = 0; i < c.resources.size(); ++i) {
    const CompiledResource& r = c.resources[i];
    if (r.image || r.imported || r.first_pass < 0) continue;
    const std::string label = "graph:" + r.name;
    phys->buffers.emplace(r.name, gpu::Buffer(ctx_, {r.size, r.buffer_usage, gpu::MemoryUsage::GpuOnly, label.c_str()}));
  }
  phys->serial = ++layouts_created_;
  layouts_.push_back(std::move(phys));
  return *layouts_.back();
}

void Executor::record_barriers(VkCommandBuffer cmd, const std::vector<Barrier>& barriers) const {
  std::vector<VkImageMemoryBarrier2> images;
  std::vector<VkBufferMemoryBarrier2> buffers;
  for (const Barrier& b : barriers) {
    if (b.image) {
      const PhysicalTexture& t = textures_[b.resource];
      const VkImageSubresourceRange all{gpu::format_aspect(t.format), 0, VK_REMAINING_MIP_LEVELS, 0,
                                        VK_REMAINING_ARRAY_LAYERS};
      images.push_back(gpu::image_barrier(t.image, all, b.old_layout, b.new_layout, b.src_stages, b.src_access,
                                          b.dst_stages, b.dst_access));
    } else {
      buffers.push_back(
          gpu::buffer_barrier(buffers_[b.resource].buffer, b.src_stages, b.src_access, b.dst_stages, b.dst_access));
    }
  }
  gpu::cmd_barriers(cmd, images, buffers);
}

// lavapipe records a timestamp when its rasterizer next runs (at the following flush), while it runs a
// compute dispatch at once: a compute pass between two timestamps measured about 0 ms and its time went
// unseen (the light grid read 0.01 ms while rebuilding it every frame cost 800 ms). An execution barrier
// right after the write makes lavapipe flush, so the timestamp is taken where it was written. On a GPU
// the barrier would only serialize passes, so only CPU devices get it.
void Executor::write_timestamp(VkCommandBuffer cmd, VkQueryPool pool, uint32_t query) const {
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool, query);
  // An execution dependency only (no access): all lavapipe needs is the flush it implies.
  if (ctx_.info().is_cpu())
    gpu::cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
}

void Executor::execute(const RenderGraph& graph, VkCommandBuffer cmd) {
  const uint64_t hash = graph.hash();
  if (!shape_ || shape_->hash != hash) {
    // A shape seen before (budget mode, debug view, a pass present only while lightning strikes)
    // comes back as it was: nothing is compiled.
    auto seen = std::find_if(shapes_.begin(), shapes_.end(), [&](const auto& p) { return p->hash == hash; });
    if (seen != shapes_.end()) {
      shape_ = seen->get();
    } else {
      shape_ = &compile_shape(graph);
      seen_.insert(hash);
    }
  }
  if (!physical_ || physical_->key != shape_->layout) physical_ = &physical_for(*shape_);
  shape_->last_used = frame_;
  physical_->last_used = frame_;
  const CompiledGraph& c = shape_->compiled;
  if (shape_->bound != physical_->serial) {
    shape_->images.assign(c.resources.size(), nullptr);
    shape_->buffers.assign(c.resources.size(), nullptr);
    for (uint32_t i = 0; i < c.resources.size(); ++i) {
      const CompiledResource& r = c.resources[i];
      if (r.imported || r.first_pass < 0) continue;
      if (r.image) shape_->images[i] = &physical_->images.at(r.name);
      else shape_->buffers[i] = &physical_->buffers.at(r.name);
    }
    shape_->bound = physical_->serial;
  }

  // Resolve handles for this frame: imported objects may change every frame (swapchain images).
  textures_.assign(c.resources.size(), {});
  buffers_.assign(c.resources.size(), {});
  for (uint32_t i = 0; i < c.resources.size(); ++i) {
    const CompiledResource& r = c.resources[i];
    if (r.imported) {
      if (r.image) {
        textures_[i] = graph.imported_texture(i);
        textures_[i].extent = r.extent;
      } else {
        buffers_[i] = graph.imported_buffer(i);
      }
    } else if (gpu::Image* transient = shape_->images[i]) {
      gpu::Image& img = *transient;
      textures_[i] = {img.handle(), img.view(), r.format, r.extent, r.mips, {}};
      if (r.mips > 1)
        for (uint32_t m = 0; m < r.mips; ++m) textures_[i].mip_views.push_back(img.mip_view(m));
    } else if (gpu::Buffer* transient = shape_->buffers[i]) {
      buffers_[i] = {transient->handle(), r.size};
    }
  }
  for (const CompiledPass& p : c.passes)
    for (const Barrier& b : p.barriers)
      if (b.image ? !textures_[b.resource].image : !buffers_[b.resource].buffer)
        fail("render graph: pass '%s' uses imported '%s' but it was imported with a null Vulkan handle", p.name.c_str(),
             b.name.c_str());

  const bool timestamps = ctx_.info().timestamps && pool_capacity_ >= 2 * c.passes.size();
  const uint32_t slot = uint32_t(frame_ % kTimestampSlots);
  VkQueryPool pool = timestamps ? pools_[slot] : VK_NULL_HANDLE;
  if (pool) vkCmdResetQueryPool(cmd, pool, 0, uint32_t(2 * c.passes.size()));

  for (uint32_t i = 0; i < c.passes.size(); ++i) {
    const CompiledPass& p = c.passes[i];
    ctx_.cmd_begin_label(cmd, p.name.c_str());
    record_barriers(cmd, p.barriers);
    // ALL_COMMANDS: the first timestamp waits for earlier passes, so a pass's range is its own work.
    if (pool) write_timestamp(cmd, pool, 2 * i);
    PassContext context(cmd, p.name, textures_, buffers_, p.accesses);
    graph.run_pass(p.declared, context);
    if (pool) write_timestamp(cmd, pool, 2 * i + 1);
    ctx_.cmd_end_label(cmd);
  }
  record_barriers(cmd, c.final_barriers);

  graph.store_persistent_states(c);  // persistent textures carry their last use into the next frame

  // Keep gpu::Image's idea of the layout current for helpers that use it (readback, uploads).
  for (uint32_t i = 0; i < c.resources.size(); ++i)
    if (shape_->images[i]) shape_->images[i]->set_layout(last_access(c, i).layout);

  std::vector<std::string>& names = slot_passes_[slot];
  names.clear();
  if (pool)
    for (const CompiledPass& p : c.passes) names.push_back(p.name);
  ++frame_;
  slot_frame_[slot] = pool ? frame_ : 0;
}

std::vector<PassTiming> Executor::timings() const {
  if (frame_ == 0) return {};
  const uint32_t last = uint32_t((frame_ - 1) % kTimestampSlots);
  return read_slot(last, slot_passes_[last]);
}

Executor::CompletedTimings Executor::latest_completed_timings() const {
  // Newest first: the slots of the last kTimestampSlots frames.
  for (uint64_t back = 0; back < kTimestampSlots && back < frame_; ++back) {
    const uint32_t slot = uint32_t((frame_ - 1 - back) % kTimestampSlots);
    if (slot_frame_[slot] != frame_ - back) continue;  // no timestamps that frame
    std::vector<PassTiming> t = read_slot(slot, slot_passes_[slot]);
    if (!t.empty()) return {slot_frame_[slot], std::move(t)};
  }
  return {};
}

std::vector<PassTiming> Executor::read_slot(uint32_t slot, const std::vector<std::string>& passes) const {
  std::vector<PassTiming> out;
  if (passes.empty()) return out;
  const uint32_t n = uint32_t(passes.size());
  std::vector<uint64_t> data(size_t(4) * n);  // (value, availability) pairs
  VkResult r =
      vkGetQueryPoolResults(ctx_.device(), pools_[slot], 0, 2 * n, data.size() * sizeof(uint64_t), data.data(),
                            2 * sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (r < 0) return out;
  const double period_ms = double(ctx_.info().limits.timestampPeriod) * 1e-6;
  for (uint32_t i = 0; i < n; ++i) {
    const uint64_t begin = data[4 * i], begin_ok = data[4 * i + 1];
    const uint64_t end = data[4 * i + 2], end_ok = data[4 * i + 3];
    if (!begin_ok || !end_ok) return {};
    if (std::optional<double> ms = timestamp_interval_ms(begin, end, period_ms)) out.push_back({passes[i], *ms});
  }
  return out;
}

std::optional<double> timestamp_interval_ms(uint64_t begin, uint64_t end, double period_ms) {
  if (end < begin) return std::nullopt;
  return double(end - begin) * period_ms;
}

double Executor::pass_ms(const std::string& pass) const {
  for (const PassTiming& t : timings())
    if (t.name == pass) return t.ms;
  return -1.0;
}

}  // namespace cumulo::render
