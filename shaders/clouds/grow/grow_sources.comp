#version 450
// Cloud-formation solver, stage 1 (solver.cpp's apply_sources): thermals at the floor. In the lowest source layers,
// theta and qv relax toward the ambient profile plus each active thermal's excess, shaped by its radial falloff and
// a seeded, slowly drifting plume-root pattern (two octaves of value noise, grow_noise.glsl). One thread per floor
// cell of the source layers. Constants (0.65/0.35 octaves, 2.3 lacunarity, 2.2 n - 0.35, 240 s drift) are the CPU's.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"
#include "clouds/grow/grow_noise.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, theta)
GROW_FIELD(2, vapour)
layout(set = 0, binding = 3, std430) readonly buffer Thermals { GrowThermal thermals[]; };
GROW_VEC4S(4, ambient)  // per level: theta0, exner, pressure, qv0

void main() {
  ivec3 n = P.dims.xyz;
  int layers = int(P.shear.z);
  int id = int(gl_GlobalInvocationID.x);
  if (id >= n.x * layers * n.z) return;
  int i = id % n.x, j = (id / n.x) % layers, k = id / (n.x * layers);
  float t = pc.step.x;
  float heat = 0.0, moist = 0.0;
  int count = grow_runtime(int(P.sources.y));
  for (int h = 0; h < count; ++h) {
    GrowThermal th = thermals[h];
    if (t < th.source.y || t > th.source.z) continue;
    vec2 d = vec2(float(i) + 0.5, float(k) + 0.5) - th.shape.xy;
    float r2 = dot(d, d) / (th.shape.z * th.shape.z);
    if (r2 >= 1.0) continue;
    float fall = (1.0 - r2) * (1.0 - r2);
    vec3 q = vec3(float(i) / P.sources.x, float(k) / P.sources.x, t / 240.0);
    float noise = 0.65 * grow_value_noise(q, th.seed.xy) +
                  0.35 * grow_value_noise(q * 2.3, th.seed.xy ^ uvec2(0xABCDu, 0u));
    float pattern = max(0.0, 2.2 * noise - 0.35);
    heat = max(heat, th.shape.w * fall * pattern);
    moist = max(moist, th.source.x * 1e-3 * fall * pattern);
  }
  if (heat <= 0.0 && moist <= 0.0) return;
  int c = grow_index(ivec3(i, j, k), n);
  vec4 a = ambient[j];
  float relax = P.shear.w;
  float th_target = a.x + heat, qv_target = a.w + moist;
  float th = theta[c], qv = vapour[c];
  if (th < th_target) theta[c] = th + (th_target - th) * relax;
  if (qv < qv_target) vapour[c] = qv + (qv_target - qv) * relax;
}
