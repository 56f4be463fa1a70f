#pragma once
// The cloud solver's pressure solve on the GPU: the CPU's problem and method (modules/clouds/bake/grow/pressure.h:
// the cell-centred 7-point Poisson problem with free-slip walls, conjugate gradients preconditioned with one
// multigrid V-cycle of red-black Gauss-Seidel, the same levels, sweeps, restriction and prolongation, the same
// stopping test and iteration cap), so that a GPU step projects as the CPU's does.
//
// The host cannot see the residual without waiting, so every one of the `max_iterations` iterations is recorded;
// the scalars (alpha, beta, the norms) live in a small state buffer the last pass of each sum writes. The solve's
// passes are indirect dispatches whose group counts the solve copies in at its start; once the stopping test
// passes, that pass empties them (GROW_STATE_DONE), and the iterations left launch nothing (a 64x32x64 grid
// converges in a few of the CPU's 40). Sums are two-pass reductions in a fixed order (no atomics): the same bytes
// every run. They are float where the CPU's are double, the only difference of the two solves.
//
//   GpuPoissonSolver poisson(ctx, library, dispatch, dims);
//   poisson.record_solve(cmd, rhs, pressure, 40);   // rhs: consumed (made mean-free); pressure: warm start, result
//   ... after the submission: poisson.last_iterations()
#include <glm/glm.hpp>
#include <vector>

#include "engine/gpu/buffer.h"
#include "modules/clouds/grow_gpu/grow_dispatch.h"

namespace cumulo::gpu {
class PipelineLibrary;
}

namespace cumulo::clouds::grow_gpu {

class GpuPoissonSolver {
 public:
  GpuPoissonSolver(gpu::Context& ctx, gpu::PipelineLibrary& library, const GrowDispatch& dispatch, glm::ivec3 dims);

  // Records the solve of A x = b on the finest level: b (cells floats) is made mean-free in place, x holds the warm
  // start and receives the result. Ends with a barrier.
  void record_solve(VkCommandBuffer cmd, VkBuffer b, VkBuffer x, int max_iterations) const;
  // The last recorded solve's CG iterations (reads the state buffer: call after its submission completed).
  int last_iterations() const;
  size_t levels() const { return levels_.size(); }

 private:
  struct Level {
    glm::ivec3 n{0};
    VkBuffer x = VK_NULL_HANDLE, b = VK_NULL_HANDLE, r = VK_NULL_HANDLE;  // level 0: z, r and a scratch residual
    uint32_t cells() const { return uint32_t(n.x) * n.y * n.z; }
  };
  struct Pipes {
    const gpu::Pipeline *apply, *residual, *smooth, *smooth_from_zero, *coarsest, *restriction, *prolongation;
    const gpu::Pipeline *partial, *final, *subtract_mean, *update_x, *update_p, *zero_x;
  };
  // The solve's indirect dispatches: per level one thread per cell and one per cell of a colour, then one group
  // and the first reduction pass's groups. Byte offsets into the dispatch buffers.
  VkDeviceSize cells_args(int level) const { return VkDeviceSize(2 * level) * 12; }
  VkDeviceSize colour_args(int level) const { return VkDeviceSize(2 * level + 1) * 12; }
  VkDeviceSize one_group_args() const { return VkDeviceSize(2 * levels_.size()) * 12; }
  VkDeviceSize partial_args() const { return VkDeviceSize(2 * levels_.size() + 1) * 12; }
  uint32_t dispatch_entries() const { return uint32_t(2 * levels_.size() + 2); }
  shared::GrowPush push_for(int level, int op = 0) const;
  void record_vcycle(VkCommandBuffer cmd, int level) const;
  void record_smooth(VkCommandBuffer cmd, int level, int colour) const;
  void record_sum(VkCommandBuffer cmd, VkBuffer a, VkBuffer b, bool sum_only, int op) const;
  void record_remove_mean(VkCommandBuffer cmd, VkBuffer a) const;
  void record_precondition(VkCommandBuffer cmd) const;

  const GrowDispatch& d_;
  Pipes pipes_{};
  std::vector<gpu::Buffer> storage_;
  std::vector<Level> levels_;
  VkBuffer r_ = VK_NULL_HANDLE, z_ = VK_NULL_HANDLE, p_ = VK_NULL_HANDLE, q_ = VK_NULL_HANDLE;
  VkBuffer partials_ = VK_NULL_HANDLE;
  gpu::Buffer state_;
  gpu::Buffer dispatch_counts_, dispatches_;  // the group counts; the solve's copy, emptied when it stops
};

}  // namespace cumulo::clouds::grow_gpu
