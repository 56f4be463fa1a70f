// The Felzenszwalb-Huttenlocher EDT against brute force.
#include <gtest/gtest.h>

#include <random>

#include "modules/clouds/bake/edt.h"

using namespace cumulo::clouds::bake;

TEST(Edt, OneDimensionalMatchesBruteForce) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    int n = 1 + rng() % 40;
    std::vector<float> f(n), d(n);
    for (float& v : f) v = (rng() % 3 == 0) ? float(rng() % 50) : kEdtInfinity;
    std::vector<int> v(n);
    std::vector<double> z(n + 1);
    float s = 0.5f + (rng() % 8);
    edt_1d(f.data(), n, s, d.data(), v.data(), z.data());
    for (int p = 0; p < n; ++p) {
      double best = kEdtInfinity;
      for (int q = 0; q < n; ++q)
        if (f[q] < kEdtInfinity) best = std::min(best, double(p - q) * (p - q) * s * s + f[q]);
      EXPECT_NEAR(d[p], best, 1e-3 * std::max(1.0, best)) << "trial " << trial << " p " << p;
    }
  }
}

TEST(Edt, ThreeDimensionalIsExactOnRandomGrids) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 12; ++trial) {
    glm::uvec3 dims(3 + rng() % 10, 3 + rng() % 10, 3 + rng() % 10);
    glm::vec3 spacing = trial % 2 ? glm::vec3(8.0f) : glm::vec3(1.0f + rng() % 4, 2.5f, 1.0f + rng() % 3);
    size_t n = size_t(dims.x) * dims.y * dims.z;
    std::vector<uint8_t> sites(n);
    int density = 2 + rng() % 30;
    for (auto& s : sites) s = rng() % density == 0;
    std::vector<float> d = squared_edt(sites, dims, spacing);
    for (uint32_t z = 0; z < dims.z; ++z)
      for (uint32_t y = 0; y < dims.y; ++y)
        for (uint32_t x = 0; x < dims.x; ++x) {
          double best = kEdtInfinity;
          for (uint32_t k = 0; k < dims.z; ++k)
            for (uint32_t j = 0; j < dims.y; ++j)
              for (uint32_t i = 0; i < dims.x; ++i)
                if (sites[i + dims.x * (j + dims.y * k)]) {
                  glm::dvec3 dv = (glm::dvec3(i, j, k) - glm::dvec3(x, y, z)) * glm::dvec3(spacing);
                  best = std::min(best, glm::dot(dv, dv));
                }
          float got = d[x + dims.x * (y + dims.y * z)];
          if (best >= kEdtInfinity)
            EXPECT_GE(got, kEdtInfinity);
          else
            EXPECT_NEAR(got, best, 1e-4 * std::max(1.0, best));
        }
  }
}
