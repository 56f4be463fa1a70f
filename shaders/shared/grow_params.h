// Parameters of the cloud-formation solver's step on the GPU (modules/clouds/grow_gpu, issue 26), shared by C++
// and GLSL. The solver is modules/clouds/bake/grow/solver.cpp; every shader of shaders/clouds/grow mirrors one of
// its stages, so the names below are the CPU's.
//
// Buffers are std430 arrays of float, index x + nx (y + ny z) as on the CPU; faces as the CPU's u, v, w.
#ifndef CUMULO_SHARED_GROW_PARAMS_H
#define CUMULO_SHARED_GROW_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

#define GROW_BINDING_PARAMS 0  // uniform GrowParams; each shader's buffers follow from binding 1
#define GROW_LOCAL_SIZE 64     // threads per group of the per-cell passes (1D over cells or faces)
#define GROW_REDUCE_SIZE 256   // threads per group of the reductions and of the coarsest pressure level
#define GROW_REDUCE_BLOCK 1024 // elements summed per group of the first reduction pass (4 per thread)

// grow_reduce_final.comp's operations (GrowPush::control.y): what it does with the finished sums
#define GROW_OP_MEAN 0     // state.mean = sum / cells (remove_mean)
#define GROW_OP_BNORM 1    // state.bnorm = |b|; a zero right-hand side ends the solve with x = 0
#define GROW_OP_RZ_INIT 2  // rz = r.z, and the first convergence test on r.r
#define GROW_OP_PQ 3       // alpha = rz / p.q (ends the solve unless p.q > 0)
#define GROW_OP_RZ_NEXT 4  // beta = r.z / rz, rz = r.z, then the convergence test on r.r

// The pressure solve's scalars (one small storage buffer): what PoissonSolver::solve keeps in locals. When `done`
// turns non-zero, grow_reduce_final.comp also empties the solve's indirect dispatches: the iterations recorded
// after convergence then launch no work.
#define GROW_STATE_MEAN 0
#define GROW_STATE_BNORM 1
#define GROW_STATE_RZ 2
#define GROW_STATE_ALPHA 3
#define GROW_STATE_BETA 4
#define GROW_STATE_DONE 5        // 0 iterating, 1 converged or stopped, 2 zero right-hand side (x = 0)
#define GROW_STATE_ITERATIONS 6  // CG iterations taken (as a float)
#define GROW_STATE_FLOATS 8

struct GrowParams {
  ivec4 dims;     // xyz: cells per axis; w: cells
  vec4 grid;      // x: cell (m); y: dt (s); z: dt / cell (m/s -> cells per step); w: the shear's reference height (cells)
  vec4 shear;     // xy: wind shear (m/s per cell of height, x and z); z: source layers; w: source relaxation per step
  vec4 sources;   // x: noise feature size (cells); y: thermal count; z: the condensation/growth averages' weight; w: condensation rate
  vec4 forces;    // x: drying fraction per step; y: drying humidity; z: confinement eps (m/s); w: 0.5 / cell (1/m)
  vec4 physics;   // atmosphere.h's constants: x latent heat (J/kg), y cp (J/(kg K)), z vapour gas constant (J/(kg K)), w g (m/s^2)
  vec4 pressure;  // x: relative tolerance; yzw: unused
};
CUMULO_SHARED_SIZE(GrowParams, 112)

// One thermal at the floor (solver.h's Thermal), in a storage buffer.
struct GrowThermal {
  vec4 shape;   // xy: position (cells, x and z); z: radius (cells); w: heat (K)
  vec4 source;  // x: moisture (g/kg); y: start (s); z: end (s); w: unused
  uvec4 seed;   // xy: low and high words of the noise seed (solver seed * 0x2545F4914F6CDD1D + thermal seed); zw: unused
};
CUMULO_SHARED_SIZE(GrowThermal, 48)

// Push constants of every grow shader (each reads what it needs).
struct GrowPush {
  ivec4 level;    // xyz: the grid a pressure pass works on (a multigrid level); w: its cells
  ivec4 coarse;   // xyz: the next coarser level (restriction, prolongation); w: its cells
  ivec4 control;  // x: red-black colour; y: GROW_OP_*; z: partial sums to fold; w: 1 for a sum, 0 for dot products
  ivec4 solve;    // x: the pressure solve's indirect dispatches (VkDispatchIndirectCommand), emptied when it stops; yzw: unused
  vec4 step;      // x: the step's start time (s); yzw: unused
};
CUMULO_SHARED_SIZE(GrowPush, 80)

CUMULO_SHARED_END

#endif
