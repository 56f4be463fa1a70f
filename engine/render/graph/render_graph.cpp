// Declaration side of the render graph: resources, passes, builder, hash, the null backend.
#include "engine/render/graph/render_graph.h"

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/gpu/format.h"
#include "engine/render/graph/detail/compiler.h"
#include "engine/render/graph/detail/graph_data.h"

namespace cumulo::render {

struct RenderGraph::Impl {
  VkExtent2D output_size{0, 0};
  std::vector<detail::ResourceDecl> resources;
  std::vector<detail::PassDecl> passes;

  uint32_t add_resource(detail::ResourceDecl r) {
    resources.push_back(std::move(r));
    return uint32_t(resources.size() - 1);
  }
  // Records the access; the version check happens in compile's validate step so that every
  // declaration error is reported in one place, naming the pass.
  uint32_t record(uint32_t pass, uint32_t resource, uint32_t version, Usage usage, bool read, bool write,
                  VkPipelineStageFlags2 stages) {
    if (resource >= resources.size())
      fail("render graph: pass '%s' uses an invalid handle (index %u)", passes[pass].name.c_str(), resource);
    passes[pass].accesses.push_back({resource, version, usage, read, write, stages});
    if (!write) return version;
    // Hand out the next version; validate() rejects a write of a version that is not the latest.
    return ++resources[resource].version;
  }
};

RenderGraph::RenderGraph(VkExtent2D output_size) : impl_(std::make_unique<Impl>()) {
  if (output_size.width == 0 || output_size.height == 0)
    fail("render graph: output size %ux%u is empty", output_size.width, output_size.height);
  impl_->output_size = output_size;
}
RenderGraph::~RenderGraph() = default;
RenderGraph::RenderGraph(RenderGraph&&) noexcept = default;
RenderGraph& RenderGraph::operator=(RenderGraph&&) noexcept = default;

TextureHandle RenderGraph::create_texture(const std::string& name, const TextureDesc& desc) {
  detail::ResourceDecl r;
  r.name = name;
  r.image = true;
  r.texture = desc;
  return {impl_->add_resource(std::move(r)), 0};
}

BufferHandle RenderGraph::create_buffer(const std::string& name, const BufferDesc& desc) {
  detail::ResourceDecl r;
  r.name = name;
  r.image = false;
  r.buffer = desc;
  return {impl_->add_resource(std::move(r)), 0};
}

TextureHandle RenderGraph::import_texture(const std::string& name, const TextureDesc& desc, VkImage image,
                                          VkImageView view, const ResourceState& initial, const ResourceState& final) {
  detail::ResourceDecl r;
  r.name = name;
  r.image = true;
  r.imported = true;
  r.texture = desc;
  r.vk_image = image;
  r.vk_view = view;
  r.initial = initial;
  r.final = final;
  return {impl_->add_resource(std::move(r)), 0};
}

TextureHandle RenderGraph::find_import(const std::string& name, VkImage image) const {
  for (uint32_t i = 0; i < impl_->resources.size(); ++i) {
    const detail::ResourceDecl& r = impl_->resources[i];
    if (r.image && r.imported && r.vk_image == image && r.name == name) return {i, 0};
  }
  return {};
}

TextureHandle RenderGraph::import_persistent(PersistentTexture& t) {
  if (t.desc.width == 0) fail("render graph: persistent texture '%s' needs an absolute size", t.name.c_str());
  TextureHandle h = import_texture(t.name, t.desc, t.image, t.view, t.state, ResourceState::undefined());
  impl_->resources[h.index].persistent = &t.state;
  return h;
}

void HistoryTexture::set_images(const TextureDesc& desc, VkImage a, VkImageView av, VkImage b, VkImageView bv) {
  images_[0] = {name_ + " [0]", desc, a, av, {}};
  images_[1] = {name_ + " [1]", desc, b, bv, {}};
  reset_ = true;
}

HistoryHandles RenderGraph::import_history(HistoryTexture& h) {
  if (!h.has_images()) fail("render graph: history '%s' has no images (set_images first)", h.name_.c_str());
  h.current_ ^= 1u;
  if (h.reset_) {
    h.frames_ = 0;
    h.reset_ = false;
  }
  HistoryHandles out;
  out.valid = h.frames_ > 0;
  ++h.frames_;
  // Named by role, not by image: the states by role repeat every frame, so the graph's shape (hash) does too.
  PersistentTexture& cur = h.images_[h.current_];
  PersistentTexture& prev = h.images_[h.current_ ^ 1u];
  out.current = import_texture(h.name_, cur.desc, cur.image, cur.view, cur.state, ResourceState::undefined());
  impl_->resources[out.current.index].persistent = &cur.state;
  out.previous = import_texture(h.name_ + " (previous)", prev.desc, prev.image, prev.view, prev.state,
                                ResourceState::undefined());
  impl_->resources[out.previous.index].persistent = &prev.state;
  return out;
}

BufferHandle RenderGraph::import_buffer(const std::string& name, VkBuffer buffer, VkDeviceSize size,
                                        const ResourceState& initial, const ResourceState& final) {
  detail::ResourceDecl r;
  r.name = name;
  r.image = false;
  r.imported = true;
  r.buffer.size = size;
  r.vk_buffer = buffer;
  r.initial = initial;
  r.final = final;
  r.initial.layout = r.final.layout = VK_IMAGE_LAYOUT_UNDEFINED;  // buffers have no layout
  return {impl_->add_resource(std::move(r)), 0};
}

void RenderGraph::add_pass(const std::string& name, Queue queue, const SetupFn& setup, ExecuteFn execute) {
  detail::PassDecl p;
  p.name = name;
  p.queue = queue;
  p.execute = std::move(execute);
  impl_->passes.push_back(std::move(p));
  PassBuilder builder(*this, uint32_t(impl_->passes.size() - 1));
  if (setup) setup(builder);
}

uint64_t RenderGraph::hash() const {
  uint64_t h = hash64(&impl_->output_size, sizeof(VkExtent2D));
  auto mix = [&h](const void* p, size_t n) { h = hash64(p, n, h); };
  auto mix_state = [&](const ResourceState& s) {
    mix(&s.layout, sizeof s.layout);
    mix(&s.stages, sizeof s.stages);
    mix(&s.access, sizeof s.access);
  };
  for (const auto& r : impl_->resources) {
    h = hash64(r.name, h);
    uint8_t kind = uint8_t(r.image) | uint8_t(r.imported) << 1;
    mix(&kind, 1);
    const TextureDesc& t = r.texture;
    mix(&t.format, sizeof t.format);
    mix(&t.size_scale, sizeof t.size_scale);
    mix(&t.width, sizeof t.width);
    mix(&t.height, sizeof t.height);
    mix(&t.depth, sizeof t.depth);
    mix(&t.mips, sizeof t.mips);
    mix(&t.type, sizeof t.type);
    mix(&r.buffer.size, sizeof r.buffer.size);
    mix_state(r.initial);
    mix_state(r.final);
    uint8_t persistent = r.persistent != nullptr;
    mix(&persistent, 1);
  }
  for (const auto& p : impl_->passes) {
    h = hash64(p.name, h);
    mix(&p.queue, sizeof p.queue);
    uint8_t side = p.side_effect;
    mix(&side, 1);
    for (const auto& a : p.accesses) {
      mix(&a.resource, sizeof a.resource);
      mix(&a.version, sizeof a.version);
      mix(&a.usage, sizeof a.usage);
      uint8_t rw = uint8_t(a.read) | uint8_t(a.write) << 1;
      mix(&rw, 1);
      mix(&a.stages, sizeof a.stages);
    }
  }
  return h;
}

CompiledGraph RenderGraph::compile(const CompileOptions& options) const {
  detail::Compiler compiler(impl_->output_size, impl_->resources, impl_->passes, options);
  CompiledGraph out = compiler.run();
  out.hash = hash();
  return out;
}

void RenderGraph::execute_without_device(const CompiledGraph& compiled) const {
  std::vector<PhysicalTexture> textures(impl_->resources.size());
  std::vector<PhysicalBuffer> buffers(impl_->resources.size());
  for (size_t i = 0; i < compiled.resources.size(); ++i) {
    const CompiledResource& r = compiled.resources[i];
    textures[i] = {VK_NULL_HANDLE, VK_NULL_HANDLE, r.format, r.extent, r.mips, {}};
    buffers[i] = {VK_NULL_HANDLE, r.size};
  }
  for (const CompiledPass& p : compiled.passes) {
    PassContext context(VK_NULL_HANDLE, p.name, textures, buffers, p.accesses);
    run_pass(p.declared, context);
  }
  store_persistent_states(compiled);
}

VkExtent2D RenderGraph::output_size() const { return impl_->output_size; }
size_t RenderGraph::pass_count() const { return impl_->passes.size(); }
const std::string& RenderGraph::pass_name(uint32_t declared) const { return impl_->passes.at(declared).name; }

PhysicalTexture RenderGraph::imported_texture(uint32_t resource) const {
  const auto& r = impl_->resources.at(resource);
  return {r.vk_image,     r.vk_view,
          r.texture.format, {r.texture.width, r.texture.height, r.texture.depth},
          r.texture.mips,   {}};
}

void RenderGraph::store_persistent_states(const CompiledGraph& c) const {
  for (uint32_t i = 0; i < c.resources.size(); ++i) {
    ResourceState* state = impl_->resources.at(i).persistent;
    const int last = c.resources[i].last_pass;
    if (!state || last < 0) continue;
    for (const ResourceAccess& a : c.passes[last].accesses)
      if (a.resource == i) *state = {a.layout, a.stages, a.access};
  }
}

PhysicalBuffer RenderGraph::imported_buffer(uint32_t resource) const {
  const auto& r = impl_->resources.at(resource);
  return {r.vk_buffer, r.buffer.size};
}

void RenderGraph::run_pass(uint32_t declared, PassContext& context) const {
  const auto& p = impl_->passes.at(declared);
  if (p.execute) p.execute(context);
}

// ---- PassBuilder ----------------------------------------------------------------------------

TextureHandle PassBuilder::read(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  graph_.impl_->record(pass_, h.index, h.version, usage, true, false, stages);
  return h;
}
TextureHandle PassBuilder::write(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  return {h.index, graph_.impl_->record(pass_, h.index, h.version, usage, false, true, stages)};
}
TextureHandle PassBuilder::read_write(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  return {h.index, graph_.impl_->record(pass_, h.index, h.version, usage, true, true, stages)};
}
BufferHandle PassBuilder::read(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  graph_.impl_->record(pass_, h.index, h.version, usage, true, false, stages);
  return h;
}
BufferHandle PassBuilder::write(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  return {h.index, graph_.impl_->record(pass_, h.index, h.version, usage, false, true, stages)};
}
BufferHandle PassBuilder::read_write(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages) {
  return {h.index, graph_.impl_->record(pass_, h.index, h.version, usage, true, true, stages)};
}
TextureHandle PassBuilder::create_texture(const std::string& name, const TextureDesc& desc) {
  return graph_.create_texture(name, desc);
}
BufferHandle PassBuilder::create_buffer(const std::string& name, const BufferDesc& desc) {
  return graph_.create_buffer(name, desc);
}
void PassBuilder::side_effect() { graph_.impl_->passes[pass_].side_effect = true; }

VkImageView PassContext::mip_view(TextureHandle h, uint32_t mip) const {
  const PhysicalTexture& t = texture(h);
  if (mip < t.mip_views.size()) return t.mip_views[mip];
  if (mip == 0 && t.mips == 1) return t.view;
  fail("render graph: pass '%s' asks for mip %u of a texture (index %u) with %zu mip views", pass_.c_str(), mip, h.index,
       t.mip_views.size());
}

VkImageLayout PassContext::layout(TextureHandle h) const {
  for (const ResourceAccess& a : accesses_)
    if (a.resource == h.index) return a.layout;
  fail("render graph: pass '%s' asks for the layout of a texture (index %u) it did not declare", pass_.c_str(),
       h.index);
}

// ---- CompiledGraph helpers ------------------------------------------------------------------

const CompiledPass* CompiledGraph::find_pass(const std::string& name) const {
  for (const auto& p : passes)
    if (p.name == name) return &p;
  return nullptr;
}

int CompiledGraph::position(const std::string& name) const {
  for (size_t i = 0; i < passes.size(); ++i)
    if (passes[i].name == name) return int(i);
  return -1;
}

bool CompiledGraph::shares_memory(uint32_t a, uint32_t b) const {
  const int ba = resources.at(a).memory_block, bb = resources.at(b).memory_block;
  return a != b && ba >= 0 && ba == bb;
}

MemoryQuery estimate_memory(const CompiledResource& r) {
  // Device-free estimate: the tightly packed mip chain (gpu/format), 64 KiB alignment (a common GPU
  // page). The executor replaces this with vkGetDeviceImageMemoryRequirements.
  // Unknown format: assume the widest common texel, 16 bytes.
  const VkFormat format = gpu::format_info(r.format).block_bytes ? r.format : VK_FORMAT_R32G32B32A32_SFLOAT;
  VkDeviceSize total = 0;
  for (uint32_t m = 0; m < r.mips; ++m) total += gpu::mip_size_bytes(format, r.extent, m);
  return {total, 65536, ~0u};
}

}  // namespace cumulo::render
