#include "modules/clouds/render/cloud_growth_runtime.h"

#include <algorithm>
#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/gpu_budget.h"
#include "modules/clouds/bake/grow/solver.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/grow_gpu/grown_asset_gpu.h"
#include "modules/clouds/volume/nvdf.h"

namespace cumulo::clouds::render {
namespace {
// The least GPU memory a growing cloud leaves for the frame's resources under a budget (beyond its own size again).
constexpr uint64_t kGrowthHeadroomMin = 8ull << 20;
}  // namespace

CloudGrowthRuntime::CloudGrowthRuntime(gpu::Context& ctx, gpu::PipelineLibrary& library,
                                       const std::filesystem::path& spec, float voxel)
    : ctx_(ctx), spec_file_(spec), spec_(grow::load_grow_spec(spec)), voxel_(voxel) {
  solver_ = std::make_unique<grow_gpu::GpuCloudSolver>(ctx, library, spec_.solver);
  grown_ = std::make_unique<grow_gpu::GpuGrownAsset>(ctx, library, spec_.solver.dims,
                                                     grow_gpu::grown_asset_settings(spec_, voxel));
  const grow_gpu::GrownAssetView v = grown_->view();
  asset_ = std::make_shared<CloudAsset>();
  asset_->folder = spec_file_;
  asset_->formats = CloudFormats::from_set(CloudFormatSet::Uncompressed);
  asset_->borrowed = {v.modeling, v.field, v.field_fair};
  asset_->has_field_fair = false;  // field_fair is one texel of -256 m, as a bake without one
  asset_->dims = v.dims;
  asset_->voxel_size = v.voxel_size;
  asset_->bounds_min = v.bounds_min;
  asset_->bounds_max = v.bounds_max;
  asset_->gpu_bytes = v.gpu_bytes;
  readback_ = make_modeling_volume(v.dims, v.voxel_size, v.bounds_min);
  readback_.bounds_max = v.bounds_max;
  restart();
}

CloudGrowthRuntime::~CloudGrowthRuntime() = default;

int CloudGrowthRuntime::steps_done() const { return solver_->steps_done(); }

void CloudGrowthRuntime::restart() {
  const grow::CloudSolver start(spec_.solver);  // the first step's state (the spec's atmosphere at rest)
  solver_->upload(start);
  const std::vector<float>& qc = start.cloud_water();
  start_cloudless_ = std::none_of(qc.begin(), qc.end(), [&](float q) { return q > spec_.iso; });
  // The images of a start with no cloud are not made: none is drawn until a step shows one (images_cloudless), so a
  // storm waiting for its event costs no update at all. Whatever the images held (the last generation's cloud) is
  // not drawn from here on: they show no step of this generation.
  dirty_ = !start_cloudless_;
  shown_step_ = -1;
  next_chunk_ = -1;  // an update under way is dropped: its scratch state came from the old generation
  readback_step_ = -1;  // the old generation's copy no longer shows the cloud
}

CloudGrowthRuntime::Plan CloudGrowthRuntime::plan(const CloudGrowthFrame& frame, int max_steps, bool spread, int slot,
                                                  int update_frames) {
  // The copy this slot's last frame made is complete (the slot's fence has been waited for): the host's now.
  if (slot >= 0 && size_t(slot) < slot_copies_.size()) {
    SlotCopy& c = slot_copies_[size_t(slot)];
    if (c.step >= 0 && c.generation == generation_ && frame.generation == generation_) {
      std::memcpy(readback_.levels[0].data(), c.buffer.mapped(), readback_.levels[0].size());
      readback_step_ = c.step;
    }
    c.step = -1;
  }
  if (!started_) {
    started_ = true;
    generation_ = frame.generation;
  } else if (frame.generation != generation_) {
    // The frames in flight may still step the old state or sample the old images (upload writes from the host).
    ctx_.wait_idle();
    restart();
    generation_ = frame.generation;
    ++restarts_;
  }
  Plan p;
  if (next_chunk_ >= 0) {
    // An update spread over frames is under way: its next run, and no step until it is done (its stages read the
    // solver's buffers).
    p.update_stages = chunks_[size_t(next_chunk_)];
    if (size_t(++next_chunk_) == chunks_.size()) {
      p.update = true;
      next_chunk_ = -1;
    }
    stepped_last_ = false;
  } else {
    const int target = std::min(frame.target_steps, spec_.steps);
    p.steps = std::clamp(target - solver_->steps_done(), 0, std::max(max_steps, 0));
    if (spread && stepped_last_ && dirty_) {
      // Last frame stepped: this one draws the images (and the light grid) from it and steps nothing, so no frame
      // pays for both. A cloud that must catch up alternates, at half the rate.
      p.steps = 0;
      p.update = true;
    } else {
      p.update = dirty_ || (!spread && p.steps > 0);
      if (spread && p.steps > 0) p.update = false;
    }
    stepped_last_ = p.steps > 0;
    if (p.update) {
      chunks_ = grown_->update_chunks(*solver_, spread ? update_frames : 1);
      p.update_stages = chunks_.front();
      if (chunks_.size() > 1) {
        p.update = false;  // the images change in the update's last frame
        next_chunk_ = 1;
      }
    }
  }
  if (p.update) {
    p.first_images = shown_step_ < 0;
    ++asset_->revision;  // this frame's graph rebuilds the images before anything samples them
    shown_step_ = solver_->steps_done() + p.steps;  // the update follows this frame's steps
  }
  if (p.update && slot >= 0) {
    if (slot_copies_.size() <= size_t(slot)) slot_copies_.resize(size_t(slot) + 1);
    SlotCopy& c = slot_copies_[size_t(slot)];
    if (!c.buffer)
      c.buffer = gpu::Buffer(ctx_, {.size = readback_.levels[0].size(),
                                    .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    .memory = gpu::MemoryUsage::Readback,
                                    .name = "grown.modeling readback"});
    p.readback_slot = slot;
  }
  return p;
}

void CloudGrowthRuntime::record_steps(VkCommandBuffer cmd, int steps) {
  for (int k = 0; k < steps; ++k) solver_->record_step(cmd);
  if (steps > 0) dirty_ = true;
}

void CloudGrowthRuntime::record_update(VkCommandBuffer cmd, grow_gpu::GrownUpdateChunk run, gpu::GpuTimer* timer,
                                       grow_gpu::GrownUpdateOrder order, int readback_slot) {
  const int updates = grown_->updates_recorded();
  grown_->record_update_stages(cmd, *solver_, run.first, run.count, timer, order);
  if (grown_->updates_recorded() == updates) return;  // not the update's last stages
  if (readback_slot >= 0 && size_t(readback_slot) < slot_copies_.size()) {
    SlotCopy& c = slot_copies_[size_t(readback_slot)];
    grown_->record_modeling_copy(cmd, c.buffer.handle());
    c.step = solver_->steps_done();
    c.generation = generation_;
  }
  dirty_ = false;
}

CloudGrowthRuntimes::~CloudGrowthRuntimes() {
  if (!runtimes_.empty()) ctx_.wait_idle();  // frames in flight may still step them or sample their images
}

CloudGrowthRuntime& CloudGrowthRuntimes::runtime(const CloudGrowthFrame& g) {
  std::unique_ptr<CloudGrowthRuntime>& r = runtimes_[g.key];
  if (r && (r->spec_file() != g.spec || r->voxel() != g.voxel)) {
    ctx_.wait_idle();
    r.reset();
  }
  if (!r) {
    const uint64_t before = ctx_.allocator().stats().allocated_bytes;
    try {
      r = std::make_unique<CloudGrowthRuntime>(ctx_, library_, g.spec, g.voxel);
    } catch (...) {  // a bad spec, the GPU budget: no runtime left behind
      runtimes_.erase(g.key);
      throw;
    }
    // A growing cloud is optional, the frame's own resources planned after it are not (the light grid grows by a
    // slab with each instance, the sky layer's maps, targets): under a budget it is kept only if as much again
    // is left, else it is not grown and the level runs without it (issue 25's budget rule for optional content).
    if (const uint64_t budget = gpu::gpu_memory_budget_bytes()) {
      const uint64_t used = ctx_.allocator().stats().allocated_bytes;
      const uint64_t own = used > before ? used - before : 0;
      const uint64_t headroom = std::max<uint64_t>(own, kGrowthHeadroomMin);
      if (used + headroom > budget) {
        const std::string message = strf(
            "a growing cloud takes %.1f MiB of GPU memory and would leave %.1f of the %.1f MiB budget, less than the "
            "%.1f MiB kept for the frame's own resources (CUMULO_GPU_MEMORY_BUDGET_MB)",
            double(own) / 1048576.0, double(budget > used ? budget - used : 0) / 1048576.0, double(budget) / 1048576.0,
            double(headroom) / 1048576.0);
        r.reset();
        runtimes_.erase(g.key);
        throw gpu::GpuBudgetError(message);
      }
    }
  }
  return *r;
}

const CloudGrowthRuntime* CloudGrowthRuntimes::find(uint64_t key) const {
  auto it = runtimes_.find(key);
  return it == runtimes_.end() ? nullptr : it->second.get();
}

CloudGrowthRuntime* CloudGrowthRuntimes::find(uint64_t key) {
  auto it = runtimes_.find(key);
  return it == runtimes_.end() ? nullptr : it->second.get();
}

void add_cloud_growth_passes(cumulo::render::RenderGraph& graph, const std::vector<CloudGrowthWork>& work) {
  using namespace cumulo::render;
  if (work.empty()) return;
  // Side effects: what they write (the solver's buffers, the grown images) is outside the graph, and the images'
  // state at the pass's end (SHADER_READ_ONLY, visible to every later command) is the state the light passes
  // import them in (cloud_growth_runtime.h says why that is enough).
  graph.add_pass(
      kGrowPass, Queue::Compute, [](PassBuilder& b) { b.side_effect(); },
      [work](PassContext& c) {
        for (const CloudGrowthWork& w : work) w.runtime->record_steps(c.cmd(), w.plan.steps);
      });
  graph.add_pass(
      kGrowAssetPass, Queue::Compute, [](PassBuilder& b) { b.side_effect(); },
      [work](PassContext& c) {
        for (const CloudGrowthWork& w : work)
          if (w.plan.update_stages.count > 0)
            w.runtime->record_update(c.cmd(), w.plan.update_stages, nullptr, grow_gpu::GrownUpdateOrder::Interleaved,
                                     w.plan.readback_slot);
      });
}

}  // namespace cumulo::clouds::render
