#pragma once
// GpuCloudSolver: one step of the cloud-formation solver (grow::CloudSolver, modules/clouds/bake/grow/solver.h) as
// compute dispatches over persistent GPU buffers, the first piece of issue 26 ("clouds that grow while you watch").
// Each stage is one shader of shaders/clouds/grow mirroring the CPU's code in its order of operations: sources,
// advection (semi-Lagrangian velocity, MacCormack scalars), phase change, drying, buoyancy, vorticity confinement,
// the projection (gpu_pressure.h: the CPU's multigrid-preconditioned CG) and the growth average. From the same state
// a GPU step matches the CPU's step within rounding (tests/modules/clouds/grow_gpu says how closely).
//
//   gpu::PipelineLibrary library(ctx);
//   grow_gpu::GpuCloudSolver gpu(ctx, library, cpu.settings());
//   gpu.upload(cpu);                                                       // continue from the CPU's state
//   ctx.submit_and_wait([&](VkCommandBuffer cmd) { gpu.record_step(cmd); gpu.record_step(cmd); });
//   std::vector<float> qc = gpu.read(grow_gpu::Field::CloudWater);        // once the submission completed
//
// Buffers hold floats in the CPU's order (x + nx (y + ny z); faces as its u, v, w) and persist from step to step:
// a renderer may read buffer(Field::CloudWater) after a step. Deterministic: no atomics, sums in a fixed order.
// Not kept on the GPU: the water budget (the sourced and dried totals) and the peak cloud water.
#include <array>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "engine/gpu/buffer.h"
#include "modules/clouds/bake/grow/solver.h"
#include "modules/clouds/grow_gpu/grow_dispatch.h"

namespace cumulo::gpu {
class PipelineLibrary;
}

namespace cumulo::clouds::grow_gpu {

class GpuPoissonSolver;

// The state a step reads and writes (units as CloudSolver's accessors).
enum class Field { U, V, W, Theta, Vapour, CloudWater, Condensation, Growth, CloudWaterBefore, Pressure, Count };

class GpuCloudSolver {
 public:
  GpuCloudSolver(gpu::Context& ctx, gpu::PipelineLibrary& library, const grow::SolverSettings& settings);
  ~GpuCloudSolver();
  GpuCloudSolver(const GpuCloudSolver&) = delete;
  GpuCloudSolver& operator=(const GpuCloudSolver&) = delete;

  // Takes the CPU solver's whole state (its settings must be this solver's): fields, the pressure's warm start, the
  // step count and the averages' memory. The GPU must be idle.
  void upload(const grow::CloudSolver& cpu);
  // Records one dt; several may follow in one command buffer. Starts and ends with a barrier.
  void record_step(VkCommandBuffer cmd);

  // Reads a field back (waits; call once the recorded steps completed).
  std::vector<float> read(Field f) const;
  // Minus the divergence the last step's projection removed (its right-hand side, made mean-free): for checks.
  std::vector<float> read_projection_rhs() const;
  VkBuffer buffer(Field f) const { return fields_[size_t(f)].handle(); }
  int steps_done() const { return steps_; }  // recorded so far
  double time() const { return steps_ * double(s_.dt); }
  int last_pressure_iterations() const;  // the last completed step's CG iterations
  const glm::ivec3& dims() const { return s_.dims; }

 private:
  struct Pipes {
    const gpu::Pipeline *sources, *advect_velocity, *advect_trace, *advect_hat, *advect_correct, *phase, *dry;
    const gpu::Pipeline *buoyancy, *vorticity_curl, *vorticity_force, *vorticity_apply, *divergence, *gradient,
        *averages;
  };
  size_t field_floats(Field f) const;
  void write_params(float condensation_memory);
  VkBuffer f(Field field) const { return fields_[size_t(field)].handle(); }

  gpu::Context& ctx_;
  grow::SolverSettings s_;
  Pipes pipes_{};
  gpu::Buffer params_;
  GrowDispatch dispatch_;
  std::array<gpu::Buffer, size_t(Field::Count)> fields_;
  // Scratch of one step: the advected and forced velocities, the advected scalars, MacCormack's traces and
  // predictors, the confinement's vorticity and force, the pressure's right-hand side.
  gpu::Buffer u_mid_, v_mid_, w_mid_, theta_mid_, vapour_mid_, water_mid_, back_, fwd_;
  gpu::Buffer theta_hat_, vapour_hat_, water_hat_, omega_, force_, rhs_;
  gpu::Buffer ambient_, thermals_;  // per level: theta0, exner, pressure, qv0; the thermals (GrowThermal)
  std::unique_ptr<GpuPoissonSolver> poisson_;
  int steps_ = 0;
};

}  // namespace cumulo::clouds::grow_gpu
