#pragma once
// The render graph: passes declare what they read and write; compile() culls, orders, computes
// lifetimes, aliases transient memory and derives every barrier (synchronization2); an Executor
// (executor.h) records the compiled graph into a command buffer. After Filament's FrameGraph
// (typed, versioned handles, setup/execute split, a graph testable with no device) and Granite's
// RenderGraph (bake() as short named steps, aliasing rules next to the code).
//
// [SECTION] Index
//   Queue, Usage                 what a pass does to a resource (-> stage, access, layout)
//   TextureDesc, BufferDesc      transient resources (size relative to the output or absolute)
//   ResourceState                the state of an imported resource before / after the graph
//   PersistentTexture            an imported texture whose state the graph carries from frame to frame
//   HistoryTexture               a persistent ping-pong pair: this frame's target + last frame's version
//   TextureHandle, BufferHandle  typed, versioned handles: a write returns the next version
//   PassBuilder                  used inside setup: read / write / read_write / create
//   PassContext                  given to execute: command buffer + resolved Vulkan objects
//   RenderGraph                  declaration: create/import resources, add_pass, compile, hash
//   Barrier, CompiledPass, ...   the compiled graph as plain structs (to_text, to_dot, write_dump)
//   Executor (executor.h)        records a graph on Vulkan: transient images, barriers, labels, timestamps
//
// [SECTION] Example
//   RenderGraph graph({320, 180});                                   // output size
//   auto out = graph.import_texture("swapchain", TextureDesc::relative(VK_FORMAT_B8G8R8A8_UNORM), image, view,
//                                   ResourceState::acquired(), ResourceState::present());
//   auto hdr = graph.create_texture("hdr", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT, 0.5f));
//   graph.add_pass("march", Queue::Compute,
//       [&](PassBuilder& b) { hdr = b.write(hdr, Usage::StorageWrite); },
//       [=](PassContext& c) { /* bind c.view(hdr) as storage image, vkCmdDispatch(c.cmd(), ...) */ });
//   graph.add_pass("tonemap", Queue::Graphics,
//       [&](PassBuilder& b) { b.read(hdr, Usage::Sampled); out = b.write(out, Usage::ColorAttachment); },
//       [=](PassContext& c) { /* vkCmdBeginRendering on c.view(out) in c.layout(out), sample c.view(hdr) */ });
//   CompiledGraph compiled = graph.compile();   // no device needed: inspect, dump, test
//   executor.execute(graph, cmd);               // executor.h: records barriers + passes
//
// Rules a declaration must follow (compile() throws cumulo::Error naming the pass and resource):
// - a write takes the current version of a resource and returns the next one; reads take the
//   current version (reading a version that was already overwritten is an error);
// - a transient must be written before it is read; a write does not preserve the previous content
//   unless the pass also reads it (use read_write: load ops, blending, read-modify-write);
// - one image layout per image per pass (Sampled + StorageWrite of the same image is an error);
// - imported resources are the outputs: the last version written into each outlives the graph, so
//   the passes it depends on are live. A pass with no live output is culled; its execute never runs;
// - every imported resource is unique (one VkImage/VkBuffer imported under two names is an error).
// - per-mip or per-layer states are not tracked: a pass that works mip by mip (mip generation)
//   declares the whole image (read_write, StorageWrite: GENERAL), writes mip k+1 from mip k through
//   PassContext::mip_view and places its own, commented barrier between mips; the graph sees the
//   whole image before and after (tests/engine/render/graph/graph_features_test.cpp builds a chain);
// - a pass whose effect the graph cannot see (a readback, a query, a host-visible write) calls
//   PassBuilder::side_effect(): it is never culled;
// - persistent textures (import_persistent, import_history) start each frame in the state the last
//   frame left them in and get no final barrier: the next frame's first use orders itself after it.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace cumulo::render {

// Which kind of pass this is; decides the shader stage of shader accesses (Compute: compute
// shader; Graphics: fragment shader unless a read/write names other stages). Every pass is
// recorded in order into one command buffer on the one graphics+compute queue (no async compute).
enum class Queue : uint8_t { Graphics, Compute };

enum class Usage : uint8_t {
  Sampled,          // texture()/texelFetch through a sampler          SHADER_READ_ONLY_OPTIMAL
  StorageRead,      // imageLoad / SSBO read                            GENERAL
  StorageWrite,     // imageStore / SSBO write                          GENERAL
  ColorAttachment,  // write; with read_write: load op LOAD or blending COLOR_ATTACHMENT_OPTIMAL
  DepthWrite,       // depth test + write                               DEPTH_STENCIL_ATTACHMENT_OPTIMAL
  DepthRead,        // depth test without writes                        DEPTH_STENCIL_READ_ONLY_OPTIMAL
  TransferSrc,      // copy/blit source                                 TRANSFER_SRC_OPTIMAL
  TransferDst,      // copy/blit/clear destination                      TRANSFER_DST_OPTIMAL
  Uniform,          // buffers only: uniform buffer
  Vertex,           // buffers only: vertex buffer
  Index,            // buffers only: index buffer
  Indirect,         // buffers only: indirect draw/dispatch arguments
};
const char* usage_name(Usage usage);

enum class ImageType : uint8_t { Image2D, Image3D };

// The size of a texture `scale` times the output's (at least 1x1): what TextureDesc::relative gets, for
// code that must know it before compile (dispatch sizes, a history's images).
inline VkExtent2D relative_extent(VkExtent2D output, float scale) {
  auto scaled = [scale](uint32_t v) { return std::max(1u, uint32_t(std::lround(double(v) * scale))); };
  return {scaled(output.width), scaled(output.height)};
}

// A transient texture: allocated (and possibly aliased) by the graph, contents live for one frame.
struct TextureDesc {
  VkFormat format = VK_FORMAT_UNDEFINED;
  float size_scale = 1.0f;         // relative to the graph's output size (when width == 0)
  uint32_t width = 0, height = 0;  // absolute size when width > 0
  uint32_t depth = 1;              // > 1 only for Image3D
  uint32_t mips = 1;
  ImageType type = ImageType::Image2D;

  static TextureDesc relative(VkFormat f, float scale = 1.0f) {
    TextureDesc d;
    d.format = f;
    d.size_scale = scale;
    return d;
  }
  static TextureDesc absolute(VkFormat f, uint32_t w, uint32_t h, uint32_t d3 = 1) {
    TextureDesc d;
    d.format = f;
    d.width = w;
    d.height = h;
    d.depth = d3;
    d.type = d3 > 1 ? ImageType::Image3D : ImageType::Image2D;
    return d;
  }
};

struct BufferDesc {
  VkDeviceSize size = 0;
};

// Layout + the accesses that touch an imported resource outside the graph. `initial` says what the
// last user before the graph did (source of the first barrier); `final` what the next user after
// the graph will do (destination of the last barrier).
struct ResourceState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;

  static ResourceState undefined() { return {}; }
  // Acquired swapchain image. The first barrier waits on these stages, so the submit must wait on
  // the acquire semaphore with a stage mask covering them (COLOR_ATTACHMENT_OUTPUT | TRANSFER |
  // COMPUTE_SHADER, or ALL_COMMANDS): then the first writer may be a draw, a copy or a dispatch.
  static ResourceState acquired() {
    return {VK_IMAGE_LAYOUT_UNDEFINED,
            VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT |
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
            0};
  }
  static ResourceState present() {
    return {VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
  }
  static ResourceState shader_read_only() {
    return {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
            VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
            VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
  }
  static ResourceState general_storage() {
    return {VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
  }
  static ResourceState host_read() {
    return {VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
  }
  bool operator==(const ResourceState&) const = default;
};

// A texture owned outside the graph (light grid, baked volumes, history) whose state the graph
// remembers: import_persistent() starts from `state`, and the executor stores the state of its last
// use back into it. The owner fills image, view and desc (absolute size); state starts undefined.
struct PersistentTexture {
  std::string name;
  TextureDesc desc;
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  ResourceState state;  // written by the executor after every frame that used it
};

// A ping-pong pair of persistent textures: each frame one is written (current) and the other holds last
// frame's (previous). import_history() flips the pair. `valid` in the handles is false on the first
// frame, after invalidate() (camera cut, resize) and after the images were replaced; passes read it to
// ignore the history. Device-free: render::GpuHistory (engine/render/history.h) owns the images.
class HistoryTexture {
 public:
  explicit HistoryTexture(std::string name = "history") : name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  void invalidate() { reset_ = true; }
  // For the owner of the images: install new images (they hold nothing yet: history invalid).
  void set_images(const TextureDesc& desc, VkImage a, VkImageView av, VkImage b, VkImageView bv);
  bool has_images() const { return images_[0].image != VK_NULL_HANDLE; }
  const TextureDesc& desc() const { return images_[0].desc; }
  uint64_t frames() const { return frames_; }  // imports since the history last became invalid

 private:
  friend class RenderGraph;
  std::string name_;
  PersistentTexture images_[2];
  uint32_t current_ = 1;  // index of this frame's target; flips on every import
  uint64_t frames_ = 0;
  bool reset_ = true;
};


// Typed, versioned handles. index: the resource; version: how many writes it has seen.
struct TextureHandle {
  uint32_t index = UINT32_MAX;
  uint32_t version = 0;
  bool valid() const { return index != UINT32_MAX; }
};
struct BufferHandle {
  uint32_t index = UINT32_MAX;
  uint32_t version = 0;
  bool valid() const { return index != UINT32_MAX; }
};

// What RenderGraph::import_history returns.
struct HistoryHandles {
  TextureHandle current;   // write this frame's result here
  TextureHandle previous;  // last frame's result (read only)
  bool valid = false;      // previous holds last frame's result
};

class RenderGraph;

// Declares the accesses of one pass; only valid inside its setup callback. `stages` overrides the
// shader stages of a shader access (Sampled/Storage/Uniform) in a graphics pass, e.g.
// VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT for a displacement map.
class PassBuilder {
 public:
  TextureHandle read(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);
  TextureHandle write(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);       // -> next version
  TextureHandle read_write(TextureHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);  // -> next version
  BufferHandle read(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);
  BufferHandle write(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);
  BufferHandle read_write(BufferHandle h, Usage usage, VkPipelineStageFlags2 stages = 0);
  TextureHandle create_texture(const std::string& name, const TextureDesc& desc);
  BufferHandle create_buffer(const std::string& name, const BufferDesc& desc);
  // The pass has an effect outside the graph's resources: it is kept even when nothing reads its outputs.
  void side_effect();

 private:
  friend class RenderGraph;
  PassBuilder(RenderGraph& graph, uint32_t pass) : graph_(graph), pass_(pass) {}
  RenderGraph& graph_;
  uint32_t pass_;
};

// Resolved Vulkan objects for one pass. Handles of any version resolve to the same objects.
// Without a device (RenderGraph::execute_without_device) every handle is VK_NULL_HANDLE.
struct PhysicalTexture {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;  // all mips, all layers
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent3D extent{0, 0, 0};
  uint32_t mips = 1;
  std::vector<VkImageView> mip_views;  // one view per mip (transients with mips > 1; imported: empty)
};
struct PhysicalBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
};

struct ResourceAccess;

class PassContext {
 public:
  PassContext(VkCommandBuffer cmd, const std::string& pass, const std::vector<PhysicalTexture>& textures,
              const std::vector<PhysicalBuffer>& buffers, const std::vector<ResourceAccess>& accesses)
      : cmd_(cmd), pass_(pass), textures_(textures), buffers_(buffers), accesses_(accesses) {}
  VkCommandBuffer cmd() const { return cmd_; }
  const std::string& pass_name() const { return pass_; }
  const PhysicalTexture& texture(TextureHandle h) const { return textures_.at(h.index); }
  VkImage image(TextureHandle h) const { return texture(h).image; }
  VkImageView view(TextureHandle h) const { return texture(h).view; }
  VkExtent3D extent(TextureHandle h) const { return texture(h).extent; }
  // A view of mip `mip` alone (storage writes of a mip chain). Throws when the graph made none.
  VkImageView mip_view(TextureHandle h, uint32_t mip) const;
  VkBuffer buffer(BufferHandle h) const { return buffers_.at(h.index).buffer; }
  VkDeviceSize buffer_size(BufferHandle h) const { return buffers_.at(h.index).size; }
  // The layout the graph put the image in for this pass (attachment infos, descriptor writes,
  // copies): use it rather than hard-coding one. Throws if the pass did not declare the image.
  VkImageLayout layout(TextureHandle h) const;

 private:
  VkCommandBuffer cmd_;
  const std::string& pass_;
  const std::vector<PhysicalTexture>& textures_;  // by resource index (textures and buffers share indices)
  const std::vector<PhysicalBuffer>& buffers_;
  const std::vector<ResourceAccess>& accesses_;  // this pass's accesses
};

using SetupFn = std::function<void(PassBuilder&)>;
using ExecuteFn = std::function<void(PassContext&)>;

// ---- The compiled graph: plain data, inspectable with no device -------------------------------

// One VkImageMemoryBarrier2 / VkBufferMemoryBarrier2, as data. Whole subresource range / whole buffer.
struct Barrier {
  uint32_t resource = 0;
  std::string name;  // resource name
  bool image = true;
  VkPipelineStageFlags2 src_stages = 0, dst_stages = 0;
  VkAccessFlags2 src_access = 0, dst_access = 0;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED, new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  bool discard = false;  // old_layout UNDEFINED on purpose: a transient's first use in the frame
};

// How one pass touches one resource (read and write merged).
struct ResourceAccess {
  uint32_t resource = 0;
  Usage usage = Usage::Sampled;
  bool read = false, write = false;
  VkPipelineStageFlags2 stages = 0;
  VkAccessFlags2 access = 0;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

struct CompiledPass {
  uint32_t declared = 0;  // index in declaration order (RenderGraph::pass_name)
  std::string name;
  Queue queue = Queue::Graphics;
  bool side_effect = false;
  std::vector<ResourceAccess> accesses;
  std::vector<Barrier> barriers;  // recorded before the pass, as one vkCmdPipelineBarrier2
};

struct CompiledResource {
  std::string name;
  bool image = true;
  bool imported = false;
  VkFormat format = VK_FORMAT_UNDEFINED;  // images
  VkExtent3D extent{0, 0, 0};             // images, resolved against the output size
  uint32_t mips = 1;
  ImageType type = ImageType::Image2D;
  VkDeviceSize size = 0;              // buffers
  VkImageUsageFlags image_usage = 0;  // union over live passes (creation flags)
  VkBufferUsageFlags buffer_usage = 0;
  int first_pass = -1, last_pass = -1;  // positions in CompiledGraph::passes; -1: unused
  int memory_block = -1;                // index in CompiledGraph::memory_blocks; -1: own memory / imported
  ResourceState initial, final;         // imported only
  bool persistent = false;              // imported with import_persistent/import_history: no final barrier
};

// A range of device memory shared by transients whose lifetimes do not overlap (each at offset 0).
struct MemoryBlock {
  VkDeviceSize size = 0, alignment = 1;
  uint32_t memory_type_bits = ~0u;
  std::vector<uint32_t> resources;  // in order of first use
};

struct CompiledGraph {
  VkExtent2D output_size{0, 0};
  uint64_t hash = 0;
  std::vector<CompiledPass> passes;         // live passes, in execution order
  std::vector<std::string> culled;          // culled pass names, declaration order
  std::vector<CompiledResource> resources;  // by resource index
  std::vector<MemoryBlock> memory_blocks;
  std::vector<Barrier> final_barriers;  // after the last pass: imported resources to their final state

  const CompiledPass* find_pass(const std::string& name) const;  // null if culled or unknown
  int position(const std::string& pass) const;                   // -1 if culled or unknown
  bool shares_memory(uint32_t a, uint32_t b) const;
  std::string to_text() const;
  std::string to_dot() const;
  // For `cumulo run --dump-graph FILE`: Graphviz when FILE ends in .dot or .gv, text otherwise.
  // Written atomically; throws cumulo::Error naming the file on failure.
  void write_dump(const std::string& path) const;
};

// Memory requirements of a transient image, as the device would report them. The default (no
// device) estimates the size from the format; the executor asks the device.
struct MemoryQuery {
  VkDeviceSize size = 0, alignment = 1;
  uint32_t memory_type_bits = ~0u;
};
using MemoryQueryFn = std::function<MemoryQuery(const CompiledResource&)>;
MemoryQuery estimate_memory(const CompiledResource& image);

struct CompileOptions {
  MemoryQueryFn memory_query;  // empty: estimate_memory
  bool alias_memory = true;    // false: every transient image gets its own memory (for debugging)
};

// ---- Declaration ----------------------------------------------------------------------------

class RenderGraph {
 public:
  explicit RenderGraph(VkExtent2D output_size);
  ~RenderGraph();
  RenderGraph(RenderGraph&&) noexcept;
  RenderGraph& operator=(RenderGraph&&) noexcept;

  TextureHandle create_texture(const std::string& name, const TextureDesc& desc);
  BufferHandle create_buffer(const std::string& name, const BufferDesc& desc);
  // Imported: owned outside the graph (swapchain, history, light grid, NVDFs). `final` defaults to `initial`.
  TextureHandle import_texture(const std::string& name, const TextureDesc& desc, VkImage image, VkImageView view,
                               const ResourceState& initial, const ResourceState& final);
  TextureHandle import_texture(const std::string& name, const TextureDesc& desc, VkImage image, VkImageView view,
                               const ResourceState& initial) {
    return import_texture(name, desc, image, view, initial, initial);
  }
  BufferHandle import_buffer(const std::string& name, VkBuffer buffer, VkDeviceSize size, const ResourceState& initial,
                             const ResourceState& final);
  // Persistent: starts from texture.state; the executor writes the state of its last use back (the
  // PersistentTexture must outlive the execution of this graph).
  TextureHandle import_persistent(PersistentTexture& texture);
  // The texture this graph imported under `name` from `image`, or an invalid handle: a read-only import two passes
  // share (names are unique in a graph), at its first version (an import nobody writes has no other).
  TextureHandle find_import(const std::string& name, VkImage image) const;
  // Flips the pair and imports both ("NAME" = this frame's target, "NAME (previous)" = last frame's).
  HistoryHandles import_history(HistoryTexture& history);

  // setup runs now; execute runs when the compiled graph is executed, only if the pass is live.
  void add_pass(const std::string& name, Queue queue, const SetupFn& setup, ExecuteFn execute);
  // Filament-style: setup fills a Data struct that execute receives (handles created in setup).
  template <class Data, class Setup, class Execute>
  const Data& add_pass(const std::string& name, Queue queue, Setup&& setup, Execute&& execute) {
    auto data = std::make_shared<Data>();
    add_pass(
        name, queue, [&](PassBuilder& b) { setup(b, *data); },
        [data, exec = std::forward<Execute>(execute)](PassContext& c) { exec(c, static_cast<const Data&>(*data)); });
    return *data;
  }

  // Hash of everything that shapes the compiled graph (names, descs, usages, states, output size),
  // not of callbacks or imported Vulkan handles: equal hash => the cached compile and physical
  // resources can be reused.
  uint64_t hash() const;
  CompiledGraph compile(const CompileOptions& options = {}) const;
  // Runs the execute callbacks of the live passes, in order, with null Vulkan handles: the "null
  // backend" of the tests (a culled pass never executes).
  void execute_without_device(const CompiledGraph& compiled) const;

  VkExtent2D output_size() const;
  size_t pass_count() const;
  const std::string& pass_name(uint32_t declared) const;
  // Executor access: imported objects and callbacks by index.
  PhysicalTexture imported_texture(uint32_t resource) const;
  PhysicalBuffer imported_buffer(uint32_t resource) const;
  // Writes the state of each persistent texture's last use back into its PersistentTexture (the
  // executor does it after recording; execute_without_device too, so compiled tests can run frames).
  void store_persistent_states(const CompiledGraph& compiled) const;
  void run_pass(uint32_t declared, PassContext& context) const;

 private:
  friend class PassBuilder;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cumulo::render
