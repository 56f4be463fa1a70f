#include "modules/clouds/grow_gpu/gpu_pressure.h"

#include <algorithm>

#include "engine/gpu/context.h"
#include "engine/gpu/pipeline_library.h"

namespace cumulo::clouds::grow_gpu {

namespace {

// The coarsest level runs in one work group when it is at most this big (every level of an even grid is); a larger
// one (a grid with an odd side has no coarser level) gets a dispatch per half sweep.
constexpr uint32_t kCoarsestInOneGroup = 4096;

uint32_t ceil_div(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

}  // namespace

GpuPoissonSolver::GpuPoissonSolver(gpu::Context& ctx, gpu::PipelineLibrary& library, const GrowDispatch& dispatch,
                                   glm::ivec3 dims)
    : d_(dispatch) {
  auto pipe = [&](const char* shader, const char* name, std::vector<gpu::ShaderDefine> defines = {}) {
    return &library.compute(
        {.shader = std::string("clouds/grow/") + shader, .defines = std::move(defines), .name = name});
  };
  pipes_.apply = pipe("grow_pressure_apply.comp", "grow.pressure_apply", {{"RESIDUAL", "0"}});
  pipes_.residual = pipe("grow_pressure_apply.comp", "grow.pressure_residual", {{"RESIDUAL", "1"}});
  pipes_.smooth = pipe("grow_pressure_smooth.comp", "grow.pressure_smooth");
  pipes_.smooth_from_zero = pipe("grow_pressure_smooth.comp", "grow.pressure_smooth_from_zero", {{"FROM_ZERO", "1"}});
  pipes_.coarsest = pipe("grow_pressure_coarsest.comp", "grow.pressure_coarsest");
  pipes_.restriction = pipe("grow_pressure_restrict.comp", "grow.pressure_restrict");
  pipes_.prolongation = pipe("grow_pressure_prolong.comp", "grow.pressure_prolong");
  pipes_.partial = pipe("grow_reduce_partial.comp", "grow.reduce_partial");
  pipes_.final = pipe("grow_reduce_final.comp", "grow.reduce_final");
  pipes_.subtract_mean = pipe("grow_subtract_mean.comp", "grow.subtract_mean");
  pipes_.update_x = pipe("grow_cg_update.comp", "grow.cg_update_x", {{"UPDATE", "0"}});
  pipes_.update_p = pipe("grow_cg_update.comp", "grow.cg_update_p", {{"UPDATE", "1"}});
  pipes_.zero_x = pipe("grow_cg_update.comp", "grow.cg_zero_x", {{"UPDATE", "2"}});

  auto buffer = [&](uint32_t floats, const char* name) {
    storage_.emplace_back(ctx, gpu::BufferDesc{std::max<uint32_t>(floats, 1) * sizeof(float),
                                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::GpuOnly, name});
    return storage_.back().handle();
  };
  // pressure.cpp's levels: halve while every side is even and at least 4, at most 8 levels.
  glm::ivec3 n = dims;
  for (;;) {
    Level l;
    l.n = n;
    const bool finest = levels_.empty();
    l.x = buffer(l.cells(), finest ? "grow.pressure z" : "grow.pressure level x");
    l.b = buffer(l.cells(), finest ? "grow.pressure r" : "grow.pressure level b");
    l.r = buffer(l.cells(), "grow.pressure level residual");
    if (finest) z_ = l.x, r_ = l.b;
    levels_.push_back(l);
    if ((n.x & 1) || (n.y & 1) || (n.z & 1) || n.x < 4 || n.y < 4 || n.z < 4 || levels_.size() >= 8) break;
    n /= 2;
  }
  const uint32_t cells = levels_[0].cells();
  p_ = buffer(cells, "grow.pressure p");
  q_ = buffer(cells, "grow.pressure q");
  partials_ = buffer(2 * ceil_div(cells, GROW_REDUCE_BLOCK), "grow.pressure partial sums");
  state_ = gpu::Buffer(ctx, {GROW_STATE_FLOATS * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             gpu::MemoryUsage::Readback, "grow.pressure state"});

  std::vector<VkDispatchIndirectCommand> counts;
  for (const Level& l : levels_) {
    counts.push_back({ceil_div(l.cells(), GROW_LOCAL_SIZE), 1, 1});
    counts.push_back({ceil_div(uint32_t((l.n.x + 1) / 2) * l.n.y * l.n.z, GROW_LOCAL_SIZE), 1, 1});
  }
  counts.push_back({1, 1, 1});
  counts.push_back({ceil_div(cells, GROW_REDUCE_BLOCK), 1, 1});
  const VkDeviceSize bytes = counts.size() * sizeof(VkDispatchIndirectCommand);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
  dispatch_counts_ = gpu::Buffer(ctx, {bytes, usage, gpu::MemoryUsage::GpuOnly, "grow.pressure dispatch counts"});
  dispatch_counts_.upload(counts.data(), bytes);
  dispatches_ = gpu::Buffer(ctx, {bytes, usage, gpu::MemoryUsage::GpuOnly, "grow.pressure dispatches"});
}

shared::GrowPush GpuPoissonSolver::push_for(int level, int op) const {
  shared::GrowPush p{};
  const Level& l = levels_[level];
  p.level = glm::ivec4(l.n, int(l.cells()));
  if (level + 1 < int(levels_.size())) {
    const Level& c = levels_[level + 1];
    p.coarse = glm::ivec4(c.n, int(c.cells()));
  }
  p.control.y = op;
  p.solve.x = int(dispatch_entries());
  return p;
}

void GpuPoissonSolver::record_smooth(VkCommandBuffer cmd, int level, int colour) const {
  const Level& l = levels_[level];
  shared::GrowPush p = push_for(level);
  p.control.x = colour;
  d_.indirect(cmd, *pipes_.smooth, {l.x, l.b, state_.handle()}, dispatches_.handle(), colour_args(level), p);
  grow_barrier(cmd);
}

// pressure.cpp's vcycle: from x = 0, 2 red-black sweeps; the residual restricted to the next level, solved there;
// its correction prolongated and added; 2 black-red sweeps. The coarsest level: 24 + 24 sweeps.
void GpuPoissonSolver::record_vcycle(VkCommandBuffer cmd, int li) const {
  const Level& l = levels_[li];
  const VkBuffer state = state_.handle(), args = dispatches_.handle();
  const bool coarsest = li + 1 == int(levels_.size());
  if (coarsest && l.cells() <= kCoarsestInOneGroup) {
    d_.indirect(cmd, *pipes_.coarsest, {l.x, l.b, state}, args, one_group_args(), push_for(li));
    grow_barrier(cmd);
    return;
  }
  const int sweeps = coarsest ? 24 : 2;
  d_.indirect(cmd, *pipes_.smooth_from_zero, {l.x, l.b, state}, args, cells_args(li), push_for(li));
  grow_barrier(cmd);
  record_smooth(cmd, li, 1);
  for (int s = 1; s < sweeps; ++s) record_smooth(cmd, li, 0), record_smooth(cmd, li, 1);
  if (!coarsest) {
    d_.indirect(cmd, *pipes_.residual, {l.x, l.b, l.r, state}, args, cells_args(li), push_for(li));
    grow_barrier(cmd);
    const Level& c = levels_[li + 1];
    d_.indirect(cmd, *pipes_.restriction, {l.r, c.b, state}, args, cells_args(li + 1), push_for(li));
    grow_barrier(cmd);
    record_vcycle(cmd, li + 1);
    d_.indirect(cmd, *pipes_.prolongation, {c.x, l.x, state}, args, cells_args(li), push_for(li));
    grow_barrier(cmd);
  }
  for (int s = 0; s < sweeps; ++s) record_smooth(cmd, li, 1), record_smooth(cmd, li, 0);
}

void GpuPoissonSolver::record_sum(VkCommandBuffer cmd, VkBuffer a, VkBuffer b, bool sum_only, int op) const {
  shared::GrowPush p = push_for(0, op);
  p.control.z = int(ceil_div(levels_[0].cells(), GROW_REDUCE_BLOCK));
  p.control.w = sum_only ? 1 : 0;
  const VkBuffer state = state_.handle(), args = dispatches_.handle();
  d_.indirect(cmd, *pipes_.partial, {a, b, partials_, state}, args, partial_args(), p);
  grow_barrier(cmd);
  d_.indirect(cmd, *pipes_.final, {partials_, state, args}, args, one_group_args(), p);
  grow_barrier(cmd);
}

void GpuPoissonSolver::record_remove_mean(VkCommandBuffer cmd, VkBuffer a) const {
  record_sum(cmd, a, a, true, GROW_OP_MEAN);
  d_.indirect(cmd, *pipes_.subtract_mean, {a, state_.handle()}, dispatches_.handle(), cells_args(0), push_for(0));
  grow_barrier(cmd);
}

// pressure.cpp's precondition: z = V-cycle(r), made mean-free.
void GpuPoissonSolver::record_precondition(VkCommandBuffer cmd) const {
  record_vcycle(cmd, 0);
  record_remove_mean(cmd, z_);
}

void GpuPoissonSolver::record_solve(VkCommandBuffer cmd, VkBuffer b, VkBuffer x, int max_iterations) const {
  const uint32_t cells = levels_[0].cells();
  const shared::GrowPush p0 = push_for(0);
  const VkBuffer state = state_.handle(), args = dispatches_.handle();
  vkCmdFillBuffer(cmd, state, 0, VK_WHOLE_SIZE, 0);  // iterating, no iterations yet
  const VkBufferCopy counts{0, 0, dispatch_counts_.size()};
  vkCmdCopyBuffer(cmd, dispatch_counts_.handle(), args, 1, &counts);
  grow_barrier(cmd);
  record_remove_mean(cmd, b);
  record_sum(cmd, b, b, false, GROW_OP_BNORM);
  d_.threads(cmd, *pipes_.zero_x, {state, x}, cells, p0);  // a zero right-hand side: x = 0, as the CPU returns
  grow_barrier(cmd);
  d_.indirect(cmd, *pipes_.residual, {x, b, r_, state}, args, cells_args(0), p0);
  grow_barrier(cmd);
  record_precondition(cmd);
  const VkBufferCopy all{0, 0, VkDeviceSize(cells) * sizeof(float)};
  vkCmdCopyBuffer(cmd, z_, p_, 1, &all);
  grow_barrier(cmd);
  record_sum(cmd, r_, z_, false, GROW_OP_RZ_INIT);
  for (int it = 0; it < max_iterations; ++it) {
    d_.indirect(cmd, *pipes_.apply, {p_, p_, q_, state}, args, cells_args(0), p0);
    grow_barrier(cmd);
    record_sum(cmd, p_, q_, false, GROW_OP_PQ);
    d_.indirect(cmd, *pipes_.update_x, {state, x, r_, p_, q_}, args, cells_args(0), p0);
    grow_barrier(cmd);
    record_precondition(cmd);
    record_sum(cmd, r_, z_, false, GROW_OP_RZ_NEXT);
    d_.indirect(cmd, *pipes_.update_p, {state, p_, z_}, args, cells_args(0), p0);
    grow_barrier(cmd);
  }
}

int GpuPoissonSolver::last_iterations() const {
  float s[GROW_STATE_FLOATS];
  state_.download(s, sizeof s);
  return int(s[GROW_STATE_ITERATIONS]);
}

}  // namespace cumulo::clouds::grow_gpu
