#include "modules/clouds/bake/grow/pressure.h"

#include <algorithm>
#include <cmath>

#include "engine/core/parallel.h"

namespace cumulo::clouds::grow {

namespace {

size_t idx(const glm::ivec3& n, int x, int y, int z) { return size_t(x) + size_t(n.x) * (size_t(y) + size_t(n.y) * z); }

// Slices per task: small levels run on one thread (spawning costs more than their work).
size_t chunk_for(const glm::ivec3& n) { return std::max<size_t>(1, 16384 / (size_t(n.x) * n.y)); }

template <class F>
void for_slices(const glm::ivec3& n, F&& f) {
  parallel_for(size_t(n.z), [&](size_t b, size_t e) {
    for (size_t z = b; z < e; ++z) f(int(z));
  }, chunk_for(n));
}

// Neighbour sum and count of cell (x, y, z) inside the box.
inline float neighbours(const glm::ivec3& n, const float* x, int i, int j, int k, size_t c, int* count) {
  float s = 0.0f;
  int m = 0;
  const size_t sy = size_t(n.x), sz = size_t(n.x) * n.y;
  if (i > 0) s += x[c - 1], ++m;
  if (i < n.x - 1) s += x[c + 1], ++m;
  if (j > 0) s += x[c - sy], ++m;
  if (j < n.y - 1) s += x[c + sy], ++m;
  if (k > 0) s += x[c - sz], ++m;
  if (k < n.z - 1) s += x[c + sz], ++m;
  *count = m;
  return s;
}

void apply(const glm::ivec3& n, const std::vector<float>& x, std::vector<float>& out) {
  for_slices(n, [&](int k) {
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        const size_t c = idx(n, i, j, k);
        int m;
        const float s = neighbours(n, x.data(), i, j, k, c, &m);
        out[c] = float(m) * x[c] - s;
      }
  });
}

void smooth(const glm::ivec3& n, std::vector<float>& x, const std::vector<float>& b, int color) {
  for_slices(n, [&](int k) {
    for (int j = 0; j < n.y; ++j)
      for (int i = ((j + k + color) & 1); i < n.x; i += 2) {
        const size_t c = idx(n, i, j, k);
        int m;
        const float s = neighbours(n, x.data(), i, j, k, c, &m);
        x[c] = (b[c] + s) / float(std::max(m, 1));
      }
  });
}

double dot(const glm::ivec3& n, const std::vector<float>& a, const std::vector<float>& b) {
  std::vector<double> part(size_t(n.z), 0.0);
  const size_t slice = size_t(n.x) * n.y;
  for_slices(n, [&](int k) {
    double s = 0.0;
    for (size_t c = k * slice; c < (k + 1) * slice; ++c) s += double(a[c]) * double(b[c]);
    part[k] = s;
  });
  double s = 0.0;
  for (double p : part) s += p;
  return s;
}

void remove_mean(const glm::ivec3& n, std::vector<float>& a) {
  std::vector<double> part(size_t(n.z), 0.0);
  const size_t slice = size_t(n.x) * n.y;
  for_slices(n, [&](int k) {
    double s = 0.0;
    for (size_t c = k * slice; c < (k + 1) * slice; ++c) s += a[c];
    part[k] = s;
  });
  double s = 0.0;
  for (double p : part) s += p;
  const float mean = float(s / double(a.size()));
  for_slices(n, [&](int k) {
    for (size_t c = k * slice; c < (k + 1) * slice; ++c) a[c] -= mean;
  });
}

}  // namespace

PoissonSolver::PoissonSolver(glm::ivec3 dims) {
  glm::ivec3 n = dims;
  for (;;) {
    Level l;
    l.n = n;
    const size_t c = size_t(n.x) * n.y * n.z;
    l.x.assign(c, 0.0f), l.b.assign(c, 0.0f), l.r.assign(c, 0.0f);
    levels_.push_back(std::move(l));
    if ((n.x & 1) || (n.y & 1) || (n.z & 1) || n.x < 4 || n.y < 4 || n.z < 4 || levels_.size() >= 8) break;
    n /= 2;
  }
  const size_t c = size_t(dims.x) * dims.y * dims.z;
  r_.assign(c, 0.0f), z_.assign(c, 0.0f), p_.assign(c, 0.0f), q_.assign(c, 0.0f);
}

void PoissonSolver::vcycle(int li) {
  Level& L = levels_[li];
  std::fill(L.x.begin(), L.x.end(), 0.0f);
  if (li + 1 == int(levels_.size())) {
    for (int s = 0; s < 24; ++s) smooth(L.n, L.x, L.b, 0), smooth(L.n, L.x, L.b, 1);
    for (int s = 0; s < 24; ++s) smooth(L.n, L.x, L.b, 1), smooth(L.n, L.x, L.b, 0);
    return;
  }
  for (int s = 0; s < 2; ++s) smooth(L.n, L.x, L.b, 0), smooth(L.n, L.x, L.b, 1);
  apply(L.n, L.x, L.r);
  for (size_t c = 0; c < L.r.size(); ++c) L.r[c] = L.b[c] - L.r[c];
  Level& C = levels_[li + 1];
  // Restriction: half the sum of the 8 children (the unit-spacing coarse operator is 1/4 of the fine
  // one per unit length squared, and the average times 4 is the sum over 2).
  for_slices(C.n, [&](int k) {
    for (int j = 0; j < C.n.y; ++j)
      for (int i = 0; i < C.n.x; ++i) {
        float s = 0.0f;
        for (int d = 0; d < 8; ++d) s += L.r[idx(L.n, 2 * i + (d & 1), 2 * j + ((d >> 1) & 1), 2 * k + (d >> 2))];
        C.b[idx(C.n, i, j, k)] = 0.5f * s;
      }
  });
  vcycle(li + 1);
  for_slices(L.n, [&](int k) {
    for (int j = 0; j < L.n.y; ++j)
      for (int i = 0; i < L.n.x; ++i) L.x[idx(L.n, i, j, k)] += C.x[idx(C.n, i / 2, j / 2, k / 2)];
  });
  for (int s = 0; s < 2; ++s) smooth(L.n, L.x, L.b, 1), smooth(L.n, L.x, L.b, 0);
}

int PoissonSolver::solve(const std::vector<float>& b_in, std::vector<float>& x, int max_iterations, float tolerance) {
  const glm::ivec3 n = levels_[0].n;
  std::vector<float> b = b_in;
  remove_mean(n, b);
  const double bnorm = std::sqrt(dot(n, b, b));
  if (bnorm <= 0.0) {
    std::fill(x.begin(), x.end(), 0.0f);
    return 0;
  }
  apply(n, x, q_);
  for (size_t c = 0; c < r_.size(); ++c) r_[c] = b[c] - q_[c];
  auto precondition = [&] {
    levels_[0].b = r_;
    vcycle(0);
    z_ = levels_[0].x;
    remove_mean(n, z_);
  };
  precondition();
  p_ = z_;
  double rz = dot(n, r_, z_);
  int it = 0;
  for (; it < max_iterations; ++it) {
    if (std::sqrt(dot(n, r_, r_)) <= tolerance * bnorm) break;
    apply(n, p_, q_);
    const double pq = dot(n, p_, q_);
    if (!(pq > 0.0)) break;
    const float alpha = float(rz / pq);
    for_slices(n, [&](int k) {
      const size_t slice = size_t(n.x) * n.y;
      for (size_t c = k * slice; c < (k + 1) * slice; ++c) x[c] += alpha * p_[c], r_[c] -= alpha * q_[c];
    });
    precondition();
    const double rz_next = dot(n, r_, z_);
    const float beta = float(rz_next / rz);
    rz = rz_next;
    for_slices(n, [&](int k) {
      const size_t slice = size_t(n.x) * n.y;
      for (size_t c = k * slice; c < (k + 1) * slice; ++c) p_[c] = z_[c] + beta * p_[c];
    });
  }
  return it;
}

}  // namespace cumulo::clouds::grow
