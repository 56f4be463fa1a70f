#version 450
// Cloud-formation solver, stage 3 (solver.cpp's phase_change; Harris et al. 2003, eqs. 11-14): vapour above
// saturation condenses and cloud water below it evaporates, `condensation rate` of the imbalance per step, with one
// Newton step of the saturation adjustment (condensing warms the air, which raises qs); latent heat warms theta.
// Also the exponential average of the phase change (kg/kg/s). Reads the advected fields, writes the step's.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, theta_in)
GROW_FIELD(2, vapour_in)
GROW_FIELD(3, water_in)
GROW_FIELD(4, theta)
GROW_FIELD(5, vapour)
GROW_FIELD(6, water)
GROW_FIELD(7, condensation)
GROW_VEC4S(8, ambient)  // per level: theta0, exner, pressure, qv0

// atmosphere.cpp's saturation_mixing_ratio (Harris eq. 12; kg/kg, K, Pa).
float saturation_mixing_ratio(float t_kelvin, float p_pa) {
  float tc = t_kelvin - 273.15;
  return 380.2 / max(p_pa, 100.0) * exp(17.67 * tc / max(tc + 243.5, 1.0));
}

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  int j = grow_coords(id, P.dims.xyz).y;
  float pi = ambient[j].y, p = ambient[j].z;
  float latent = P.physics.x, cp = P.physics.y, rv = P.physics.z;
  float th = theta_in[id], qv = vapour_in[id], qc = water_in[id];
  float t = th * pi;
  float qs = saturation_mixing_ratio(t, p);
  float gain = 1.0 + latent * latent * qs / (cp * rv * t * t);
  float dq = P.sources.w * (qv - qs) / gain;
  if (dq < 0.0) dq = max(dq, -qc);
  vapour[id] = qv - dq;
  water[id] = qc + dq;
  theta[id] = th + latent / (cp * pi) * dq;
  float cond = condensation[id];
  condensation[id] = cond + (dq / P.grid.y - cond) * P.sources.z;
}
