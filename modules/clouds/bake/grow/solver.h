#pragma once
// The cloud-formation solver behind `cumulo grow` (the 2023 talk's Aero: "streamlined and enhanced to
// simulate only cloud growth"). The standard cloud-dynamics formulation of Miyazaki et al. 2001 and
// Harris et al. 2003, on a staggered (MAC) voxel grid, in physical units:
//
//   advection   MacCormack (second order, clamped to the semi-Lagrangian stencil's range) of the
//               velocity, the potential-temperature perturbation theta', vapour qv and cloud water qc,
//               by the flow plus the ambient wind shear
//   buoyancy    B = g ((theta' + 0.61 theta0 (qv - qv0)) / theta0 - qc)       (Harris eq. 7, virtual
//               temperature with the drag of the condensed water)
//   phase       qv -> qc where qv > qs(T, p), qc -> qv where qv < qs, at `condensation_rate` of the
//               imbalance per step; latent heat theta' += L / (cp Pi) dq      (Harris eqs. 11-14)
//   vorticity   confinement f = eps dx (N x omega), N = grad|omega| / |grad|omega||   (Fedkiw 2001):
//               the billows the grid's numerical viscosity would smooth away
//   projection  incompressible; pressure by conjugate gradients preconditioned with a geometric
//               multigrid V-cycle (red-black Gauss-Seidel), free-slip walls
//   sources     thermals at the floor: theta' and qv relaxed toward a target excess with a seeded,
//               slowly changing noise pattern (many plume roots, as a heated surface has)
//
// Determinism: every cell is written by exactly one loop iteration, Gauss-Seidel is red-black, and
// every sum is taken per z slice then added in slice order, so the bytes do not depend on the thread
// count. Grid axes are the engine's (x, y up, z); index x + nx (y + ny z).
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/bake/grow/atmosphere.h"

namespace cumulo::clouds::grow {

struct Thermal {
  glm::vec2 position{0.0f};  // cells, horizontal (x, z), from the grid's corner
  float radius = 4.0f;       // cells
  float heat = 2.0f;         // K of theta' excess at the centre of the source
  float moisture = 2.0f;     // g/kg of vapour excess at the centre
  uint32_t seed = 1;
  float start = 0.0f, end = 1.0e9f;  // physical seconds the source is on
};

struct SolverSettings {
  glm::ivec3 dims{32, 16, 32};
  float cell = 100.0f;  // physical metres per cell
  float dt = 10.0f;     // physical seconds per step
  AtmosphereSettings atmosphere;
  std::vector<Thermal> thermals;
  glm::vec2 wind_shear{0.0f};  // m/s of relative horizontal wind per physical km above the floor
  float vorticity = 0.25f;     // confinement strength (grid units)
  float condensation_rate = 0.5f;  // fraction of the imbalance exchanged per step
  float source_time = 60.0f;       // s: relaxation time of the floor toward a thermal's excess
  float noise_cells = 2.5f;        // feature size of the source pattern, cells
  float drying_start = 1.0e9f;     // s: from here the air dries (a decaying cloud): qv relaxes down
  float drying_rate = 0.0f;        // 1/s
  float drying_humidity = 0.5f;    // toward this fraction of the ambient vapour
  uint64_t seed = 1;
  int pressure_iterations = 40;    // CG cap per step
  float pressure_tolerance = 1e-4f;  // relative residual
};

struct WaterBudget {
  double initial = 0, sourced = 0, dried = 0, final_total = 0;  // kg/kg summed over cells (vapour + cloud water)
  double final_cloud_water = 0, peak_cloud_water = 0;
  // What advection created or destroyed (semi-Lagrangian schemes are not conservative): final - (initial
  // + sourced - dried), and that over the water the run added.
  double advection_residual = 0;
};

class PoissonSolver;

inline constexpr float kCondensationMemory = 300.0f;  // s: CloudSolver::condensation_memory's default

class CloudSolver {
 public:
  explicit CloudSolver(const SolverSettings& s);
  ~CloudSolver();

  void step();  // one dt
  int steps_done() const { return steps_; }
  double time() const { return steps_ * double(s_.dt); }

  const glm::ivec3& dims() const { return n_; }
  const Atmosphere& atmosphere() const { return atm_; }
  size_t cells() const { return size_t(n_.x) * n_.y * n_.z; }
  size_t index(int x, int y, int z) const { return size_t(x) + size_t(n_.x) * (size_t(y) + size_t(n_.y) * size_t(z)); }

  // Cell-centred fields.
  const std::vector<float>& cloud_water() const { return qc_; }   // kg/kg
  const std::vector<float>& vapour() const { return qv_; }        // kg/kg
  const std::vector<float>& potential_temperature() const { return th_; }  // K (the full theta)
  // Exponential average of the phase change (kg/kg/s; > 0 condensing, < 0 evaporating) over the
  // last ~`condensation_memory` seconds: where cloud water is being made or lost.
  const std::vector<float>& condensation() const { return cond_; }
  // Exponential average of the local change of cloud water d(qc)/dt at a fixed point (kg/kg/s) over
  // the same memory: > 0 where the cloud grows into the air (rising tops, towers), < 0 where it retreats.
  const std::vector<float>& growth() const { return growth_; }
  std::vector<float> vertical_velocity() const;  // m/s, cell centres
  std::vector<float> speed() const;              // m/s, cell centres

  // The raw state, for a solver that continues from it (grow_gpu::GpuCloudSolver::upload).
  const SolverSettings& settings() const { return s_; }
  const std::vector<float>& velocity_u() const { return u_; }  // m/s on x faces: (nx+1) ny nz
  const std::vector<float>& velocity_v() const { return v_; }  // on y faces: nx (ny+1) nz
  const std::vector<float>& velocity_w() const { return w_; }  // on z faces: nx ny (nz+1)
  const std::vector<float>& pressure() const { return pressure_; }  // the last solve's (the next one's warm start)
  const std::vector<float>& previous_cloud_water() const { return qc_prev_; }  // qc at the last growth update

  WaterBudget budget() const;
  int last_pressure_iterations() const { return last_cg_; }
  float max_velocity() const;
  float condensation_memory = kCondensationMemory;  // s

  // The phase change alone (public for the conservation test).
  void phase_change();

 private:
  void apply_sources();
  void advect();
  void add_forces();
  void project();
  void dry();
  double total_water() const;

  SolverSettings s_;
  glm::ivec3 n_;
  Atmosphere atm_;
  std::vector<float> u_, v_, w_;  // faces: (nx+1) ny nz, nx (ny+1) nz, nx ny (nz+1)
  std::vector<float> th_, qv_, qc_, cond_, growth_, qc_prev_;
  std::vector<float> pressure_;   // warm start of the solve
  std::vector<float> qv0_;        // ambient vapour per level
  std::unique_ptr<PoissonSolver> poisson_;
  int steps_ = 0;
  int last_cg_ = 0;
  double initial_water_ = 0, sourced_ = 0, dried_ = 0, peak_qc_ = 0;
};

}  // namespace cumulo::clouds::grow
