#pragma once
// The pressure solve of the cloud solver: the cell-centred 7-point Poisson problem with free-slip
// (Neumann) walls, A x = b with A = -Laplacian in unit spacing, by conjugate gradients preconditioned
// with one geometric multigrid V-cycle (McAdams et al. 2010, "A parallel multigrid Poisson solver for
// fluids simulation on large grids", without their irregular domains). The V-cycle is symmetric
// (red-black pre-smoothing, black-red post-smoothing, piecewise-constant prolongation whose transpose
// is the restriction), so it is a valid CG preconditioner. Constants are the null space: b is made
// mean-free and so is each preconditioned residual.
//
// Deterministic: red-black sweeps and per-slice partial sums added in slice order.
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds::grow {

class PoissonSolver {
 public:
  explicit PoissonSolver(glm::ivec3 dims);
  // Solves A x = b; x holds the initial guess (warm start) and the result. Returns the iterations.
  int solve(const std::vector<float>& b, std::vector<float>& x, int max_iterations, float tolerance);

 private:
  struct Level {
    glm::ivec3 n;
    std::vector<float> x, b, r;
  };
  void vcycle(int l);
  std::vector<Level> levels_;
  std::vector<float> r_, z_, p_, q_;
};

}  // namespace cumulo::clouds::grow
