#include "modules/clouds/grow_gpu/gpu_solver.h"

#include <algorithm>
#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline_library.h"
#include "modules/clouds/grow_gpu/gpu_pressure.h"

namespace cumulo::clouds::grow_gpu {

namespace {

gpu::Buffer storage(gpu::Context& ctx, size_t bytes, const char* name) {
  return gpu::Buffer(ctx,
                     {std::max<size_t>(bytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::GpuOnly, name});
}

// solver.cpp's apply_sources: the layers the thermals heat and moisten.
int source_layers(const glm::ivec3& n) { return std::max(1, std::min(2, n.y / 8)); }

}  // namespace

GpuCloudSolver::GpuCloudSolver(gpu::Context& ctx, gpu::PipelineLibrary& library, const grow::SolverSettings& settings)
    : ctx_(ctx),
      s_(settings),
      params_(ctx, {sizeof(shared::GrowParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                    "grow.params"}),
      dispatch_(ctx, params_.handle()) {
  const glm::ivec3 n = s_.dims;
  if (n.x < 4 || n.y < 4 || n.z < 4)
    fail("grow_gpu: the grid needs at least 4 cells per axis (got %dx%dx%d)", n.x, n.y, n.z);
  auto pipe = [&](const char* shader, const char* name) {
    return &library.compute({.shader = std::string("clouds/grow/") + shader, .name = name});
  };
  pipes_.sources = pipe("grow_sources.comp", "grow.sources");
  pipes_.advect_velocity = pipe("grow_advect_velocity.comp", "grow.advect_velocity");
  pipes_.advect_trace = pipe("grow_advect_trace.comp", "grow.advect_trace");
  pipes_.advect_hat = pipe("grow_advect_hat.comp", "grow.advect_hat");
  pipes_.advect_correct = pipe("grow_advect_correct.comp", "grow.advect_correct");
  pipes_.phase = pipe("grow_phase.comp", "grow.phase");
  pipes_.dry = pipe("grow_dry.comp", "grow.dry");
  pipes_.buoyancy = pipe("grow_buoyancy.comp", "grow.buoyancy");
  pipes_.vorticity_curl = pipe("grow_vorticity_curl.comp", "grow.vorticity_curl");
  pipes_.vorticity_force = pipe("grow_vorticity_force.comp", "grow.vorticity_force");
  pipes_.vorticity_apply = pipe("grow_vorticity_apply.comp", "grow.vorticity_apply");
  pipes_.divergence = pipe("grow_divergence.comp", "grow.divergence");
  pipes_.gradient = pipe("grow_gradient.comp", "grow.gradient");
  pipes_.averages = pipe("grow_averages.comp", "grow.averages");

  static const char* const kNames[] = {"grow.u",
                                       "grow.v",
                                       "grow.w",
                                       "grow.theta",
                                       "grow.vapour",
                                       "grow.cloud_water",
                                       "grow.condensation",
                                       "grow.growth",
                                       "grow.cloud_water_before",
                                       "grow.pressure"};
  static_assert(std::size(kNames) == size_t(Field::Count));
  for (size_t i = 0; i < size_t(Field::Count); ++i)
    fields_[i] = storage(ctx, field_floats(Field(i)) * sizeof(float), kNames[i]);
  const size_t cells = size_t(n.x) * n.y * n.z, bytes = cells * sizeof(float);
  u_mid_ = storage(ctx, field_floats(Field::U) * sizeof(float), "grow.u forced");
  v_mid_ = storage(ctx, field_floats(Field::V) * sizeof(float), "grow.v forced");
  w_mid_ = storage(ctx, field_floats(Field::W) * sizeof(float), "grow.w forced");
  theta_mid_ = storage(ctx, bytes, "grow.theta advected");
  vapour_mid_ = storage(ctx, bytes, "grow.vapour advected");
  water_mid_ = storage(ctx, bytes, "grow.cloud_water advected");
  theta_hat_ = storage(ctx, bytes, "grow.theta predicted");
  vapour_hat_ = storage(ctx, bytes, "grow.vapour predicted");
  water_hat_ = storage(ctx, bytes, "grow.cloud_water predicted");
  back_ = storage(ctx, 4 * bytes, "grow.trace back");
  fwd_ = storage(ctx, 4 * bytes, "grow.trace forward");
  omega_ = storage(ctx, 4 * bytes, "grow.vorticity");
  force_ = storage(ctx, 4 * bytes, "grow.confinement force");
  rhs_ = storage(ctx, bytes, "grow.pressure rhs");

  const grow::Atmosphere atm(s_.atmosphere, n.y, s_.cell);  // the CPU solver's, from the same settings
  std::vector<glm::vec4> ambient(n.y);
  for (int j = 0; j < n.y; ++j) ambient[j] = {atm.theta(j), atm.exner(j), atm.pressure(j), atm.vapour(j)};
  ambient_ = storage(ctx, ambient.size() * sizeof(glm::vec4), "grow.ambient");
  ambient_.upload(ambient.data(), ambient.size() * sizeof(glm::vec4));

  std::vector<shared::GrowThermal> thermals;
  for (const grow::Thermal& t : s_.thermals) {
    const uint64_t seed = s_.seed * 0x2545F4914F6CDD1Dull + t.seed;  // solver.cpp's apply_sources
    thermals.push_back({glm::vec4(t.position, t.radius, t.heat), glm::vec4(t.moisture, t.start, t.end, 0.0f),
                        glm::uvec4(uint32_t(seed), uint32_t(seed >> 32), 0u, 0u)});
  }
  thermals_ = storage(ctx, std::max<size_t>(thermals.size(), 1) * sizeof(shared::GrowThermal), "grow.thermals");
  if (!thermals.empty()) thermals_.upload(thermals.data(), thermals.size() * sizeof(shared::GrowThermal));

  poisson_ = std::make_unique<GpuPoissonSolver>(ctx, library, dispatch_, n);
  write_params(grow::kCondensationMemory);
}

GpuCloudSolver::~GpuCloudSolver() = default;

size_t GpuCloudSolver::field_floats(Field f) const {
  const glm::ivec3 n = s_.dims;
  switch (f) {
    case Field::U:
      return size_t(n.x + 1) * n.y * n.z;
    case Field::V:
      return size_t(n.x) * (n.y + 1) * n.z;
    case Field::W:
      return size_t(n.x) * n.y * (n.z + 1);
    default:
      return size_t(n.x) * n.y * n.z;
  }
}

// The step's constants, each computed as solver.cpp computes it.
void GpuCloudSolver::write_params(float condensation_memory) {
  const glm::ivec3 n = s_.dims;
  shared::GrowParams p{};
  p.dims = glm::ivec4(n, n.x * n.y * n.z);
  p.grid = glm::vec4(s_.cell, s_.dt, s_.dt / s_.cell, 0.5f * n.y);
  const glm::vec2 shear = s_.wind_shear * (s_.cell / 1000.0f);
  p.shear = glm::vec4(shear, float(source_layers(n)), std::min(1.0f, s_.dt / std::max(s_.source_time, 1e-3f)));
  p.sources =
      glm::vec4(s_.noise_cells, float(s_.thermals.size()), std::min(1.0f, s_.dt / std::max(condensation_memory, s_.dt)),
                std::clamp(s_.condensation_rate, 0.0f, 1.0f));
  p.forces =
      glm::vec4(std::min(1.0f, s_.drying_rate * s_.dt), s_.drying_humidity, s_.vorticity * 10.0f, 0.5f / s_.cell);
  p.physics = glm::vec4(grow::kLatentHeat, grow::kHeatCapacityAir, grow::kVapourGasConstant, grow::kGravity);
  p.pressure = glm::vec4(s_.pressure_tolerance, 0.0f, 0.0f, 0.0f);
  std::memcpy(params_.mapped(), &p, sizeof p);
}

void GpuCloudSolver::upload(const grow::CloudSolver& cpu) {
  if (cpu.dims() != s_.dims)
    fail("grow_gpu: upload of a %dx%dx%d solver into a %dx%dx%d one", cpu.dims().x, cpu.dims().y, cpu.dims().z,
         s_.dims.x, s_.dims.y, s_.dims.z);
  auto put = [&](Field field, const std::vector<float>& v) {
    if (v.size() != field_floats(field))
      fail("grow_gpu: field %d has %zu floats, expected %zu", int(field), v.size(), field_floats(field));
    fields_[size_t(field)].upload(v.data(), v.size() * sizeof(float));
  };
  put(Field::U, cpu.velocity_u());
  put(Field::V, cpu.velocity_v());
  put(Field::W, cpu.velocity_w());
  put(Field::Theta, cpu.potential_temperature());
  put(Field::Vapour, cpu.vapour());
  put(Field::CloudWater, cpu.cloud_water());
  put(Field::Condensation, cpu.condensation());
  put(Field::Growth, cpu.growth());
  put(Field::CloudWaterBefore, cpu.previous_cloud_water());
  put(Field::Pressure, cpu.pressure());
  steps_ = cpu.steps_done();
  write_params(cpu.condensation_memory);
}

std::vector<float> GpuCloudSolver::read(Field field) const {
  std::vector<float> out(field_floats(field));
  fields_[size_t(field)].download(out.data(), out.size() * sizeof(float));
  return out;
}

std::vector<float> GpuCloudSolver::read_projection_rhs() const {
  std::vector<float> out(size_t(s_.dims.x) * s_.dims.y * s_.dims.z);
  rhs_.download(out.data(), out.size() * sizeof(float));
  return out;
}

int GpuCloudSolver::last_pressure_iterations() const { return poisson_->last_iterations(); }

void GpuCloudSolver::record_step(VkCommandBuffer cmd) {
  const glm::ivec3 n = s_.dims;
  const uint32_t cells = uint32_t(n.x) * n.y * n.z;
  const uint32_t faces = uint32_t(field_floats(Field::U) + field_floats(Field::V) + field_floats(Field::W));
  const GrowDispatch& d = dispatch_;
  const VkBuffer u = f(Field::U), v = f(Field::V), w = f(Field::W), th = f(Field::Theta), qv = f(Field::Vapour),
                 qc = f(Field::CloudWater);
  shared::GrowPush push{};
  push.step.x = float(time());  // solver.cpp's apply_sources: float(time())

  gpu::ScopedLabel label(ctx_, cmd, "grow.step");
  grow_barrier(cmd);  // after what came before: an upload, the last step
  d.threads(cmd, *pipes_.sources, {th, qv, thermals_.handle(), ambient_.handle()},
            uint32_t(n.x) * source_layers(n) * n.z, push);
  grow_barrier(cmd);
  // Advection: the velocity and the scalars' traces both read the flow before the step.
  d.threads(cmd, *pipes_.advect_velocity, {u, v, w, u_mid_.handle(), v_mid_.handle(), w_mid_.handle()}, faces);
  d.threads(cmd, *pipes_.advect_trace, {u, v, w, back_.handle(), fwd_.handle()}, cells);
  grow_barrier(cmd);
  d.threads(cmd, *pipes_.advect_hat,
            {back_.handle(), th, qv, qc, theta_hat_.handle(), vapour_hat_.handle(), water_hat_.handle()}, cells);
  grow_barrier(cmd);
  d.threads(cmd, *pipes_.advect_correct,
            {back_.handle(), fwd_.handle(), th, qv, qc, theta_hat_.handle(), vapour_hat_.handle(), water_hat_.handle(),
             theta_mid_.handle(), vapour_mid_.handle(), water_mid_.handle()},
            cells);
  grow_barrier(cmd);
  d.threads(cmd, *pipes_.phase,
            {theta_mid_.handle(), vapour_mid_.handle(), water_mid_.handle(), th, qv, qc, f(Field::Condensation),
             ambient_.handle()},
            cells);
  grow_barrier(cmd);
  if (!(time() < s_.drying_start || s_.drying_rate <= 0.0f)) {  // solver.cpp's dry
    d.threads(cmd, *pipes_.dry, {qv, ambient_.handle()}, cells);
    grow_barrier(cmd);
  }
  d.threads(cmd, *pipes_.buoyancy, {th, qv, qc, ambient_.handle(), v_mid_.handle()}, uint32_t(field_floats(Field::V)));
  grow_barrier(cmd);
  if (s_.vorticity > 0.0f) {
    d.threads(cmd, *pipes_.vorticity_curl, {u_mid_.handle(), v_mid_.handle(), w_mid_.handle(), omega_.handle()}, cells);
    grow_barrier(cmd);
    d.threads(cmd, *pipes_.vorticity_force, {omega_.handle(), force_.handle()}, cells);
    grow_barrier(cmd);
    d.threads(cmd, *pipes_.vorticity_apply, {force_.handle(), u_mid_.handle(), v_mid_.handle(), w_mid_.handle()},
              faces);
    grow_barrier(cmd);
  }
  d.threads(cmd, *pipes_.divergence, {u_mid_.handle(), v_mid_.handle(), w_mid_.handle(), rhs_.handle()}, cells);
  grow_barrier(cmd);
  poisson_->record_solve(cmd, rhs_.handle(), f(Field::Pressure), s_.pressure_iterations);
  d.threads(cmd, *pipes_.gradient, {u_mid_.handle(), v_mid_.handle(), w_mid_.handle(), f(Field::Pressure), u, v, w},
            faces);
  d.threads(cmd, *pipes_.averages, {qc, f(Field::CloudWaterBefore), f(Field::Growth)}, cells);
  grow_barrier(cmd);
  ++steps_;
}

}  // namespace cumulo::clouds::grow_gpu
