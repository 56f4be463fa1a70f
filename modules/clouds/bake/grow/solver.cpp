#include "modules/clouds/bake/grow/solver.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/parallel.h"
#include "modules/clouds/bake/grow/pressure.h"

namespace cumulo::clouds::grow {

namespace {

template <class F>
void for_slices(int nz, size_t slice_cells, F&& f) {
  parallel_for(size_t(nz), [&](size_t b, size_t e) {
    for (size_t z = b; z < e; ++z) f(int(z));
  }, std::max<size_t>(1, 16384 / std::max<size_t>(slice_cells, 1)));
}

// Trilinear sample of a grid of dims `d` at continuous index coordinates (clamped to the grid).
inline float sample(const float* g, const glm::ivec3& d, glm::vec3 p) {
  p = glm::clamp(p, glm::vec3(0.0f), glm::vec3(d - 1));
  const int x0 = std::min(int(p.x), d.x - 2 < 0 ? 0 : d.x - 2), y0 = std::min(int(p.y), d.y - 2 < 0 ? 0 : d.y - 2),
            z0 = std::min(int(p.z), d.z - 2 < 0 ? 0 : d.z - 2);
  const int x1 = std::min(x0 + 1, d.x - 1), y1 = std::min(y0 + 1, d.y - 1), z1 = std::min(z0 + 1, d.z - 1);
  const float fx = p.x - x0, fy = p.y - y0, fz = p.z - z0;
  const size_t sy = size_t(d.x), sz = size_t(d.x) * d.y;
  auto at = [&](int x, int y, int z) { return g[size_t(x) + sy * y + sz * z]; };
  const float c00 = at(x0, y0, z0) + (at(x1, y0, z0) - at(x0, y0, z0)) * fx;
  const float c10 = at(x0, y1, z0) + (at(x1, y1, z0) - at(x0, y1, z0)) * fx;
  const float c01 = at(x0, y0, z1) + (at(x1, y0, z1) - at(x0, y0, z1)) * fx;
  const float c11 = at(x0, y1, z1) + (at(x1, y1, z1) - at(x0, y1, z1)) * fx;
  const float c0 = c00 + (c10 - c00) * fy, c1 = c01 + (c11 - c01) * fy;
  return c0 + (c1 - c0) * fz;
}

// Range of the 8 nodes around p (MacCormack's clamp).
inline void node_range(const float* g, const glm::ivec3& d, glm::vec3 p, float* lo, float* hi) {
  p = glm::clamp(p, glm::vec3(0.0f), glm::vec3(d - 1));
  const int x0 = int(p.x), y0 = int(p.y), z0 = int(p.z);
  const int x1 = std::min(x0 + 1, d.x - 1), y1 = std::min(y0 + 1, d.y - 1), z1 = std::min(z0 + 1, d.z - 1);
  const size_t sy = size_t(d.x), sz = size_t(d.x) * d.y;
  float a = 1e30f, b = -1e30f;
  for (int c = 0; c < 8; ++c) {
    const float v = g[size_t((c & 1) ? x1 : x0) + sy * ((c & 2) ? y1 : y0) + sz * ((c & 4) ? z1 : z0)];
    a = std::min(a, v), b = std::max(b, v);
  }
  *lo = a, *hi = b;
}

// Value noise in [0, 1] on an integer lattice hashed from the seed (the thermals' plume roots).
inline float lattice(int x, int y, int z, uint64_t seed) {
  uint64_t h = seed ^ (uint64_t(uint32_t(x)) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(uint32_t(y)) * 0xC2B2AE3D27D4EB4Full) ^
               (uint64_t(uint32_t(z)) * 0x165667B19E3779F9ull);
  h ^= h >> 33, h *= 0xff51afd7ed558ccdull, h ^= h >> 33, h *= 0xc4ceb9fe1a85ec53ull, h ^= h >> 33;
  return float(h >> 40) * (1.0f / 16777216.0f);
}
float value_noise(glm::vec3 p, uint64_t seed) {
  const glm::vec3 f = glm::floor(p);
  const glm::ivec3 i(f);
  glm::vec3 t = p - f;
  t = t * t * (3.0f - 2.0f * t);
  float r = 0.0f;
  for (int c = 0; c < 8; ++c) {
    const float w = ((c & 1) ? t.x : 1 - t.x) * ((c & 2) ? t.y : 1 - t.y) * ((c & 4) ? t.z : 1 - t.z);
    r += w * lattice(i.x + (c & 1), i.y + ((c >> 1) & 1), i.z + ((c >> 2) & 1), seed);
  }
  return r;
}

}  // namespace

CloudSolver::CloudSolver(const SolverSettings& s) : s_(s), n_(s.dims), atm_(s.atmosphere, s.dims.y, s.cell) {
  if (n_.x < 4 || n_.y < 4 || n_.z < 4) fail("grow: the grid needs at least 4 cells per axis (got %dx%dx%d)", n_.x, n_.y, n_.z);
  const size_t c = cells();
  u_.assign(size_t(n_.x + 1) * n_.y * n_.z, 0.0f);
  v_.assign(size_t(n_.x) * (n_.y + 1) * n_.z, 0.0f);
  w_.assign(size_t(n_.x) * n_.y * (n_.z + 1), 0.0f);
  th_.resize(c), qv_.resize(c), qc_.assign(c, 0.0f), cond_.assign(c, 0.0f), growth_.assign(c, 0.0f), qc_prev_.assign(c, 0.0f), pressure_.assign(c, 0.0f);
  qv0_.resize(n_.y);
  for (int j = 0; j < n_.y; ++j) qv0_[j] = atm_.vapour(j);
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) th_[index(i, j, k)] = atm_.theta(j), qv_[index(i, j, k)] = qv0_[j];
  initial_water_ = total_water();
  poisson_ = std::make_unique<PoissonSolver>(n_);
}

CloudSolver::~CloudSolver() = default;

double CloudSolver::total_water() const {
  std::vector<double> part(n_.z, 0.0);
  const size_t slice = size_t(n_.x) * n_.y;
  for_slices(n_.z, slice, [&](int k) {
    double s = 0;
    for (size_t c = k * slice; c < (k + 1) * slice; ++c) s += double(qv_[c]) + double(qc_[c]);
    part[k] = s;
  });
  double s = 0;
  for (double p : part) s += p;
  return s;
}

void CloudSolver::apply_sources() {
  const float t = float(time());
  const size_t slice = size_t(n_.x) * n_.y;
  const int layers = std::max(1, std::min(2, n_.y / 8));
  const float relax = std::min(1.0f, s_.dt / std::max(s_.source_time, 1e-3f));
  std::vector<double> added(n_.z, 0.0);
  for_slices(n_.z, slice, [&](int k) {
    for (int j = 0; j < layers; ++j)
      for (int i = 0; i < n_.x; ++i) {
        float heat = 0.0f, moist = 0.0f;
        for (const Thermal& th : s_.thermals) {
          if (t < th.start || t > th.end) continue;
          const glm::vec2 d = glm::vec2(i + 0.5f, k + 0.5f) - th.position;
          const float r2 = glm::dot(d, d) / (th.radius * th.radius);
          if (r2 >= 1.0f) continue;
          const float fall = (1.0f - r2) * (1.0f - r2);
          // Plume roots: two octaves of value noise over the floor, drifting slowly in time.
          const glm::vec3 q(float(i) / s_.noise_cells, float(k) / s_.noise_cells, t / 240.0f);
          const uint64_t seed = s_.seed * 0x2545F4914F6CDD1Dull + th.seed;
          const float n = 0.65f * value_noise(q, seed) + 0.35f * value_noise(q * 2.3f, seed ^ 0xABCDull);
          const float pattern = std::max(0.0f, 2.2f * n - 0.35f);
          heat = std::max(heat, th.heat * fall * pattern);
          moist = std::max(moist, th.moisture * 1e-3f * fall * pattern);
        }
        if (heat <= 0.0f && moist <= 0.0f) continue;
        const size_t c = index(i, j, k);
        const float th_target = atm_.theta(j) + heat, qv_target = qv0_[j] + moist;
        if (th_[c] < th_target) th_[c] += (th_target - th_[c]) * relax;
        if (qv_[c] < qv_target) {
          const float dq = (qv_target - qv_[c]) * relax;
          qv_[c] += dq;
          added[k] += dq;
        }
      }
  });
  for (double a : added) sourced_ += a;
}

void CloudSolver::advect() {
  const glm::ivec3 du(n_.x + 1, n_.y, n_.z), dv(n_.x, n_.y + 1, n_.z), dw(n_.x, n_.y, n_.z + 1);
  const std::vector<float> u0 = u_, v0 = v_, w0 = w_;
  const float scale = s_.dt / s_.cell;  // m/s -> cells per step
  const float ref_height = 0.5f * n_.y;
  const glm::vec2 shear = s_.wind_shear * (s_.cell / 1000.0f);  // m/s per cell of height
  // Velocity in cells per step at a point in cell units (cell centres at i + 0.5).
  auto vel = [&](glm::vec3 p) {
    glm::vec3 r(sample(u0.data(), du, p - glm::vec3(0.0f, 0.5f, 0.5f)), sample(v0.data(), dv, p - glm::vec3(0.5f, 0.0f, 0.5f)),
                sample(w0.data(), dw, p - glm::vec3(0.5f, 0.5f, 0.0f)));
    const float h = std::clamp(p.y, 0.0f, float(n_.y)) - ref_height;
    r.x += shear.x * h, r.z += shear.y * h;
    return r * scale;
  };
  auto trace = [&](glm::vec3 p, float dir) {
    const glm::vec3 mid = p + 0.5f * dir * vel(p);
    return p + dir * vel(mid);
  };

  // Velocity: semi-Lagrangian (vorticity confinement restores what it smooths).
  auto advect_face = [&](std::vector<float>& dst, const std::vector<float>& src, glm::ivec3 d, glm::vec3 offset) {
    for_slices(d.z, size_t(d.x) * d.y, [&](int k) {
      for (int j = 0; j < d.y; ++j)
        for (int i = 0; i < d.x; ++i) {
          const glm::vec3 p = glm::vec3(i, j, k) + offset;
          dst[size_t(i) + size_t(d.x) * (j + size_t(d.y) * k)] = sample(src.data(), d, trace(p, -1.0f) - offset);
        }
    });
  };
  advect_face(u_, u0, du, glm::vec3(0.0f, 0.5f, 0.5f));
  advect_face(v_, v0, dv, glm::vec3(0.5f, 0.0f, 0.5f));
  advect_face(w_, w0, dw, glm::vec3(0.5f, 0.5f, 0.0f));
  // Walls: no flow through them.
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j) u_[size_t(0) + du.x * (j + size_t(du.y) * k)] = 0, u_[size_t(n_.x) + du.x * (j + size_t(du.y) * k)] = 0;
  for (int k = 0; k < n_.z; ++k)
    for (int i = 0; i < n_.x; ++i) v_[size_t(i) + dv.x * (0 + size_t(dv.y) * k)] = 0, v_[size_t(i) + dv.x * (n_.y + size_t(dv.y) * k)] = 0;
  for (int j = 0; j < n_.y; ++j)
    for (int i = 0; i < n_.x; ++i) w_[size_t(i) + dw.x * (j + size_t(dw.y) * 0)] = 0, w_[size_t(i) + dw.x * (j + size_t(dw.y) * n_.z)] = 0;

  // Scalars: MacCormack with one backward and one forward trace shared by theta, qv and qc.
  const size_t c = cells();
  std::vector<glm::vec3> back(c), fwd(c);
  const glm::vec3 half(0.5f);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const glm::vec3 p = glm::vec3(i, j, k) + half;
        back[index(i, j, k)] = trace(p, -1.0f) - half;
        fwd[index(i, j, k)] = trace(p, 1.0f) - half;
      }
  });
  std::vector<float> hat(c), tilde(c);
  for (std::vector<float>* f : {&th_, &qv_, &qc_}) {
    std::vector<float>& phi = *f;
    for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
      const size_t b = size_t(k) * n_.x * n_.y, e = b + size_t(n_.x) * n_.y;
      for (size_t i = b; i < e; ++i) hat[i] = sample(phi.data(), n_, back[i]);
    });
    for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
      const size_t b = size_t(k) * n_.x * n_.y, e = b + size_t(n_.x) * n_.y;
      for (size_t i = b; i < e; ++i) tilde[i] = sample(hat.data(), n_, fwd[i]);
    });
    for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
      const size_t b = size_t(k) * n_.x * n_.y, e = b + size_t(n_.x) * n_.y;
      for (size_t i = b; i < e; ++i) {
        float lo, hi;
        node_range(phi.data(), n_, back[i], &lo, &hi);
        tilde[i] = std::clamp(hat[i] + 0.5f * (phi[i] - tilde[i]), lo, hi);
      }
    });
    phi.swap(tilde);
  }
}

void CloudSolver::phase_change() {
  const float rate = std::clamp(s_.condensation_rate, 0.0f, 1.0f);
  const float ema = std::min(1.0f, s_.dt / std::max(condensation_memory, s_.dt));
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j) {
      const float pi = atm_.exner(j), p = atm_.pressure(j);
      for (int i = 0; i < n_.x; ++i) {
        const size_t c = index(i, j, k);
        const float t = th_[c] * pi;
        const float qs = saturation_mixing_ratio(t, p);
        // One Newton step of the saturation adjustment: condensing warms the air, which raises qs.
        const float gain = 1.0f + kLatentHeat * kLatentHeat * qs / (kHeatCapacityAir * kVapourGasConstant * t * t);
        float dq = rate * (qv_[c] - qs) / gain;
        if (dq < 0.0f) dq = std::max(dq, -qc_[c]);
        qv_[c] -= dq;
        qc_[c] += dq;
        th_[c] += kLatentHeat / (kHeatCapacityAir * pi) * dq;
        cond_[c] += (dq / s_.dt - cond_[c]) * ema;
      }
    }
  });
}

void CloudSolver::add_forces() {
  const size_t c = cells();
  std::vector<float> buoy(c);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j) {
      const float th0 = atm_.theta(j);
      for (int i = 0; i < n_.x; ++i) {
        const size_t x = index(i, j, k);
        buoy[x] = kGravity * ((th_[x] - th0 + 0.61f * th0 * (qv_[x] - qv0_[j])) / th0 - qc_[x]);
      }
    }
  });
  const glm::ivec3 dv(n_.x, n_.y + 1, n_.z);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 1; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i)
        v_[size_t(i) + dv.x * (j + size_t(dv.y) * k)] += s_.dt * 0.5f * (buoy[index(i, j - 1, k)] + buoy[index(i, j, k)]);
  });

  if (s_.vorticity <= 0.0f) return;
  // Cell-centred velocity and vorticity (1/s).
  const glm::ivec3 du(n_.x + 1, n_.y, n_.z), dw(n_.x, n_.y, n_.z + 1);
  std::vector<glm::vec3> vel(c), omega(c);
  std::vector<float> mag(c);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i)
        vel[index(i, j, k)] = 0.5f * glm::vec3(u_[i + du.x * (j + size_t(du.y) * k)] + u_[i + 1 + du.x * (j + size_t(du.y) * k)],
                                               v_[i + dv.x * (j + size_t(dv.y) * k)] + v_[i + dv.x * (j + 1 + size_t(dv.y) * k)],
                                               w_[i + dw.x * (j + size_t(dw.y) * k)] + w_[i + dw.x * (j + size_t(dw.y) * (k + 1))]);
  });
  const float inv2h = 0.5f / s_.cell;
  auto clampi = [](int a, int n) { return a < 0 ? 0 : (a >= n ? n - 1 : a); };
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const glm::vec3 xp = vel[index(clampi(i + 1, n_.x), j, k)], xm = vel[index(clampi(i - 1, n_.x), j, k)];
        const glm::vec3 yp = vel[index(i, clampi(j + 1, n_.y), k)], ym = vel[index(i, clampi(j - 1, n_.y), k)];
        const glm::vec3 zp = vel[index(i, j, clampi(k + 1, n_.z))], zm = vel[index(i, j, clampi(k - 1, n_.z))];
        const glm::vec3 o((yp.z - ym.z - (zp.y - zm.y)) * inv2h, (zp.x - zm.x - (xp.z - xm.z)) * inv2h,
                          (xp.y - xm.y - (yp.x - ym.x)) * inv2h);
        omega[index(i, j, k)] = o;
        mag[index(i, j, k)] = glm::length(o);
      }
  });
  std::vector<glm::vec3> force(c);
  // Fedkiw's eps h (N x omega) with eps h = vorticity x 10 m/s: the force per step is about `vorticity`
  // of the cell-scale velocity difference for cells crossed in ~h / 10 m/s, whatever the cell size.
  const float eps = s_.vorticity * 10.0f;
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const glm::vec3 g(mag[index(clampi(i + 1, n_.x), j, k)] - mag[index(clampi(i - 1, n_.x), j, k)],
                          mag[index(i, clampi(j + 1, n_.y), k)] - mag[index(i, clampi(j - 1, n_.y), k)],
                          mag[index(i, j, clampi(k + 1, n_.z))] - mag[index(i, j, clampi(k - 1, n_.z))]);
        const float len = glm::length(g);
        force[index(i, j, k)] = len > 1e-12f ? eps * glm::cross(g / len, omega[index(i, j, k)]) : glm::vec3(0.0f);
      }
  });
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const glm::vec3 f = force[index(i, j, k)] * s_.dt;
        if (i > 0) u_[i + du.x * (j + size_t(du.y) * k)] += 0.5f * (f.x + force[index(i - 1, j, k)].x * s_.dt);
        if (j > 0) v_[i + dv.x * (j + size_t(dv.y) * k)] += 0.5f * (f.y + force[index(i, j - 1, k)].y * s_.dt);
        if (k > 0) w_[i + dw.x * (j + size_t(dw.y) * k)] += 0.5f * (f.z + force[index(i, j, k - 1)].z * s_.dt);
      }
  });
}

void CloudSolver::project() {
  const glm::ivec3 du(n_.x + 1, n_.y, n_.z), dv(n_.x, n_.y + 1, n_.z), dw(n_.x, n_.y, n_.z + 1);
  const size_t c = cells();
  std::vector<float> rhs(c);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const float div = u_[i + 1 + du.x * (j + size_t(du.y) * k)] - u_[i + du.x * (j + size_t(du.y) * k)] +
                          v_[i + dv.x * (j + 1 + size_t(dv.y) * k)] - v_[i + dv.x * (j + size_t(dv.y) * k)] +
                          w_[i + dw.x * (j + size_t(dw.y) * (k + 1))] - w_[i + dw.x * (j + size_t(dw.y) * k)];
        rhs[index(i, j, k)] = -div;
      }
  });
  last_cg_ = poisson_->solve(rhs, pressure_, s_.pressure_iterations, s_.pressure_tolerance);
  const std::vector<float>& p = pressure_;
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const float pc = p[index(i, j, k)];
        if (i > 0) u_[i + du.x * (j + size_t(du.y) * k)] -= pc - p[index(i - 1, j, k)];
        if (j > 0) v_[i + dv.x * (j + size_t(dv.y) * k)] -= pc - p[index(i, j - 1, k)];
        if (k > 0) w_[i + dw.x * (j + size_t(dw.y) * k)] -= pc - p[index(i, j, k - 1)];
      }
  });
}

void CloudSolver::dry() {
  if (time() < s_.drying_start || s_.drying_rate <= 0.0f) return;
  const float f = std::min(1.0f, s_.drying_rate * s_.dt);
  std::vector<double> removed(n_.z, 0.0);
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    for (int j = 0; j < n_.y; ++j) {
      const float target = s_.drying_humidity * qv0_[j];
      for (int i = 0; i < n_.x; ++i) {
        const size_t c = index(i, j, k);
        if (qv_[c] <= target) continue;
        const float d = (qv_[c] - target) * f;
        qv_[c] -= d;
        removed[k] += d;
      }
    }
  });
  for (double r : removed) dried_ += r;
}

void CloudSolver::step() {
  apply_sources();
  advect();
  phase_change();
  dry();
  add_forces();
  project();
  ++steps_;
  const float ema = std::min(1.0f, s_.dt / std::max(condensation_memory, s_.dt));
  for_slices(n_.z, size_t(n_.x) * n_.y, [&](int k) {
    const size_t b = size_t(k) * n_.x * n_.y, e = b + size_t(n_.x) * n_.y;
    for (size_t i = b; i < e; ++i) {
      growth_[i] += ((qc_[i] - qc_prev_[i]) / s_.dt - growth_[i]) * ema;
      qc_prev_[i] = qc_[i];
    }
  });
  double qc = 0;
  for (float q : qc_) qc += q;
  peak_qc_ = std::max(peak_qc_, qc);
}

std::vector<float> CloudSolver::vertical_velocity() const {
  std::vector<float> out(cells());
  const glm::ivec3 dv(n_.x, n_.y + 1, n_.z);
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i)
        out[index(i, j, k)] = 0.5f * (v_[i + dv.x * (j + size_t(dv.y) * k)] + v_[i + dv.x * (j + 1 + size_t(dv.y) * k)]);
  return out;
}

float CloudSolver::max_velocity() const {
  float m = 0.0f;
  for (float a : u_) m = std::max(m, std::abs(a));
  for (float a : v_) m = std::max(m, std::abs(a));
  for (float a : w_) m = std::max(m, std::abs(a));
  return m;
}

WaterBudget CloudSolver::budget() const {
  WaterBudget b;
  b.initial = initial_water_;
  b.sourced = sourced_;
  b.dried = dried_;
  b.final_total = total_water();
  for (float q : qc_) b.final_cloud_water += q;
  b.peak_cloud_water = peak_qc_;
  b.advection_residual = b.final_total - (b.initial + b.sourced - b.dried);
  return b;
}

}  // namespace cumulo::clouds::grow
