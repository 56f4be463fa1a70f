#include "modules/clouds/render/cloud_growth_runtime.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "modules/clouds/bake/grow/solver.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/grow_gpu/grown_asset_gpu.h"

namespace cumulo::clouds::render {

CloudGrowthRuntime::CloudGrowthRuntime(gpu::Context& ctx, gpu::PipelineLibrary& library,
                                       const std::filesystem::path& spec)
    : ctx_(ctx), spec_file_(spec), spec_(grow::load_grow_spec(spec)) {
  solver_ = std::make_unique<grow_gpu::GpuCloudSolver>(ctx, library, spec_.solver);
  grown_ =
      std::make_unique<grow_gpu::GpuGrownAsset>(ctx, library, spec_.solver.dims, grow_gpu::grown_asset_settings(spec_));
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
  restart();
}

CloudGrowthRuntime::~CloudGrowthRuntime() = default;

int CloudGrowthRuntime::steps_done() const { return solver_->steps_done(); }

void CloudGrowthRuntime::restart() {
  const grow::CloudSolver start(spec_.solver);  // the first step's state (the spec's atmosphere at rest)
  solver_->upload(start);
  dirty_ = true;
}

CloudGrowthRuntime::Plan CloudGrowthRuntime::plan(const CloudGrowthFrame& frame, int max_steps) {
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
  const int target = std::min(frame.target_steps, spec_.steps);
  p.steps = std::clamp(target - solver_->steps_done(), 0, std::max(max_steps, 0));
  p.update = p.steps > 0 || dirty_;
  return p;
}

void CloudGrowthRuntime::record_steps(VkCommandBuffer cmd, int steps) {
  for (int k = 0; k < steps; ++k) solver_->record_step(cmd);
  if (steps > 0) dirty_ = true;
}

void CloudGrowthRuntime::record_update(VkCommandBuffer cmd) {
  grown_->record_update(cmd, *solver_);
  dirty_ = false;
}

CloudGrowthRuntimes::~CloudGrowthRuntimes() {
  if (!runtimes_.empty()) ctx_.wait_idle();  // frames in flight may still step them or sample their images
}

CloudGrowthRuntime& CloudGrowthRuntimes::runtime(const CloudGrowthFrame& g) {
  std::unique_ptr<CloudGrowthRuntime>& r = runtimes_[g.key];
  if (r && r->spec_file() != g.spec) {
    ctx_.wait_idle();
    r.reset();
  }
  if (!r) {
    try {
      r = std::make_unique<CloudGrowthRuntime>(ctx_, library_, g.spec);
    } catch (...) {  // a bad spec, the GPU budget: no runtime left behind
      runtimes_.erase(g.key);
      throw;
    }
  }
  return *r;
}

const CloudGrowthRuntime* CloudGrowthRuntimes::find(uint64_t key) const {
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
          if (w.plan.update) w.runtime->record_update(c.cmd());
      });
}

}  // namespace cumulo::clouds::render
