#pragma once
// Executor: records a RenderGraph into a command buffer on a gpu::Context.
//
//   render::Executor executor(ctx);
//   for (each frame) {
//     RenderGraph graph(output_size);  ... declare imports and passes ...
//     executor.execute(graph, cmd);    // compiles only when graph.hash() changed
//     submit cmd, wait (or fence) ...
//     executor.timings();              // per-pass GPU ms of the last executed frame, once complete
//   }
//
// What execute() does:
// - compiles are cached by the graph's hash (up to kMaxShapes shapes, CPU data only), and the
//   transient images, buffers and memory by the compiled memory layout (up to kMaxLayouts): shapes that
//   differ only in passes on imported resources (a light grid rebuilt on some frames, an atmosphere LUT
//   updated when the sun moves, a lightning pass) share one layout, so a new shape of a known layout
//   allocates nothing and never waits for the device. A new layout is allocated beside the others; only
//   when that cache is full is the least recently used layout freed, after waiting for the device (rare:
//   simplicity wins over deferred deletion). Two shapes share a layout only when their blocks, occupants
//   and each occupant's last use are the same, so the barrier a frame's first use of a block derives from
//   its own shape also covers what any other shape of that layout did in the frame before;
// - persistent textures (RenderGraph::import_persistent / import_history) get the state of their last
//   use written back, so the next frame's graph starts from it;
// - transient images are created unbound, their real memory requirements fed to compile() so that
//   aliasing uses the device's sizes, then bound to one allocation per memory block (gpu allocator);
// - per pass: one vkCmdPipelineBarrier2 with the compiled barriers, a debug label with the pass
//   name, a timestamp before and after; then the final barriers of the imported resources;
// - objects are named after their graph resource ("graph:<name>") for validation messages/captures.
// Frames may overlap on the GPU (several in flight on the one queue): every transient's first use
// waits on the previous frame's last use of its memory (see barriers.cpp), and the timestamp pools
// rotate over kTimestampSlots frames.
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::render {

struct PassTiming {
  std::string name;
  double ms = 0.0;
};

// Milliseconds between a pass's begin and end timestamps (ticks of `period_ms`); nullopt when the end
// precedes the begin (a driver fault, or a counter with fewer than 64 valid bits wrapping): such a
// timing is left out, never clamped to 0, so it cannot pass for a fast pass.
std::optional<double> timestamp_interval_ms(uint64_t begin, uint64_t end, double period_ms);

class Executor {
 public:
  static constexpr uint32_t kTimestampSlots = 3;
  static constexpr size_t kMaxShapes = 64;  // compiled graphs (CPU data)
  static constexpr size_t kMaxLayouts = 8;  // transient memory layouts (device memory)

  explicit Executor(gpu::Context& ctx);
  ~Executor();  // the caller makes sure the GPU no longer uses the recorded command buffers
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  // Compiles (if needed) and records every live pass of `graph` into `cmd` (in the recording
  // state, outside a render pass). Throws cumulo::Error on a bad declaration.
  void execute(const RenderGraph& graph, VkCommandBuffer cmd);

  const CompiledGraph& compiled() const;  // of the last execute(); throws before the first
  bool has_executed() const { return shape_ != nullptr; }
  // Per-pass GPU milliseconds of the last executed frame, in execution order; empty while its
  // command buffer has not completed, or when the queue has no timestamps. A pass whose timestamps
  // are out of order is left out (see timestamp_interval_ms).
  std::vector<PassTiming> timings() const;
  // The newest frame whose timestamps have all arrived (frames in flight: usually one or two frames before
  // the last recorded): its number (1-based, increasing; 0 when none has completed yet) and timings.
  struct CompletedTimings {
    uint64_t frame = 0;
    std::vector<PassTiming> passes;
  };
  CompletedTimings latest_completed_timings() const;
  double pass_ms(const std::string& pass) const;  // -1 when unknown or not available

  // Counters for tests and stats: how often the graph was compiled / how many transient layouts,
  // images and memory blocks were created since construction.
  uint32_t compile_count() const { return compile_count_; }
  uint32_t layouts_created() const { return layouts_created_; }
  uint32_t images_created() const { return images_created_; }
  uint32_t memory_blocks_created() const { return blocks_created_; }
  VkDeviceSize transient_bytes() const;  // memory held by the transient blocks and buffers of every cached layout
  size_t shape_count() const;            // compiled shapes cached
  size_t layout_count() const;           // transient memory layouts cached
  size_t transient_image_count() const;  // transient images held by the cached layouts
  size_t shapes_seen() const { return seen_.size(); }  // distinct shapes (hashes) compiled since construction
  // The physical object behind a resource of the last execute() (imported ones as imported).
  const PhysicalTexture& texture(uint32_t resource) const;

 private:
  struct Physical;
  struct Shape;
  Shape& compile_shape(const RenderGraph& graph);
  Physical& physical_for(const Shape& shape);
  VkMemoryRequirements image_requirements(const CompiledResource& r);
  void record_barriers(VkCommandBuffer cmd, const std::vector<Barrier>& barriers) const;
  void write_timestamp(VkCommandBuffer cmd, VkQueryPool pool, uint32_t query) const;

  gpu::Context& ctx_;
  std::vector<std::unique_ptr<Shape>> shapes_;
  std::vector<std::unique_ptr<Physical>> layouts_;
  Shape* shape_ = nullptr;        // the shape of the last execute()
  Physical* physical_ = nullptr;  // its layout's objects
  std::unordered_map<uint64_t, VkMemoryRequirements> requirements_;  // by image description
  std::unordered_set<uint64_t> seen_;
  std::vector<PhysicalTexture> textures_;  // by resource index, resolved per frame
  std::vector<PhysicalBuffer> buffers_;
  VkQueryPool pools_[kTimestampSlots] = {};
  uint32_t pool_capacity_ = 0;            // queries per pool
  uint64_t frame_ = 0;                    // frames executed
  // Per timestamp slot (frame f, 0-based, uses slot f % kTimestampSlots): the frame (1-based; 0: none) whose
  // timestamps it holds, and its pass names in order.
  uint64_t slot_frame_[kTimestampSlots] = {};
  std::vector<std::string> slot_passes_[kTimestampSlots];
  std::vector<PassTiming> read_slot(uint32_t slot, const std::vector<std::string>& passes) const;
  uint32_t compile_count_ = 0, images_created_ = 0, blocks_created_ = 0, layouts_created_ = 0;
};

}  // namespace cumulo::render
