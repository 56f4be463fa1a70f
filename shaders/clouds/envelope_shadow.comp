#version 450
// The Envelope method's clouds' shadow on the terrain (issue 24; modules/clouds/render/envelope_layer.h): per texel of a
// horizontal plane under the envelope (render::LightShadowMap), the key light's transmittance along its ray through the
// plane point, from where the ray leaves the envelope's top down to the first terrain it meets coming down: the highest
// surface on that ray, the one the light reaches (a lower one is in the terrain's own shadow). The geometry projects a
// point along the light onto the plane, so every lit surface point reads its own ray's transmittance.
// The density is the march's light samples' (no high-frequency erosion), sampled in the middle of equal steps where
// the ray is inside a texel's conservative column, 0 elsewhere (envelope_maps.h: nothing lies outside it).
#extension GL_GOOGLE_include_directive : require
#include "clouds/envelope_density.glsl"
#include "engine/runtime_uniform.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ENV_BINDING_TERRAIN) uniform sampler2D terrain_tex;
layout(set = 0, binding = ENV_BINDING_SHADOW_OUT, r16f) uniform writeonly image2D shadow_out;
layout(push_constant) uniform Push { EnvelopeShadowPush pc; };

const float kMaxSteps = 256.0;

// The terrain's height (world y), or -1e9 outside its square (the envelope has no density there either).
float terrain_height(vec2 xz) {
  vec2 uv = (xz - pc.terrain.xy) / pc.terrain.z;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return -1e9;
  return textureLod(terrain_tex, uv, 0.0).r;
}

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(shadow_out);
  if (any(greaterThanEqual(texel, size))) return;
  vec2 xz = pc.plane.xy + (vec2(texel) + 0.5) / vec2(size) * pc.plane.zw;
  // runtime_zero(): the light's direction decides branches below, and lavapipe would otherwise keep a compiled variant
  // for every sun position it saw (the soak's dusk: +35 KB held and a ~20 MB compile a lap).
  vec3 l = normalize(pc.light.xyz) + runtime_zero();
  vec3 q = vec3(xz.x, pc.light.w, xz.y);
  // The stretch of the ray over the map's square, below the envelope's top: [t0, t1], walked from t1 down.
  float t1 = max((E.heights.y - q.y) / max(l.y, 1e-3), 0.0);
  float t0 = 0.0;
  vec2 lo = E.map.xy, hi = E.map.xy + vec2(E.map.z * E.map.w);
  for (int a = 0; a < 2; ++a) {
    if (abs(l[a * 2]) < 1e-6) {
      if (q[a * 2] < lo[a] || q[a * 2] > hi[a]) t1 = -1.0;
      continue;
    }
    float ta = (lo[a] - q[a * 2]) / l[a * 2], tb = (hi[a] - q[a * 2]) / l[a * 2];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  float od = 0.0;
  if (t1 > t0) {
    float n = min(ceil((t1 - t0) / max(pc.terrain.w, 0.5)), kMaxSteps);
    float dt = (t1 - t0) / max(n, 1.0);
    for (int i = 0; i < runtime_int(n); ++i) {
      float t = t1 - (float(i) + 0.5) * dt;
      vec3 p = q + l * t;
      if (p.y < terrain_height(p.xz)) break;  // the lit surface: what lies below is in the terrain's shadow
      vec4 s = texelFetch(steps_tex, env_texel(p.xz), 0);
      if (p.y > s.x || p.y < s.y) continue;
      od += envelope_sample(p, false).density * dt;
    }
  }
  imageStore(shadow_out, texel, vec4(exp(-od * E.wind.w), 0.0, 0.0, 0.0));
}
