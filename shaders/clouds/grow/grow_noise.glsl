// The thermals' plume-root pattern of the cloud-formation solver (solver.cpp's lattice and value_noise): value noise
// on an integer lattice hashed with 64-bit multiplies (splitmix constants, murmur3's finaliser), here on pairs of
// 32-bit words (low, high) so that no 64-bit integer support is needed. The same seed gives the CPU's exact
// lattice values; the interpolation rounds as the CPU's does.
#ifndef CUMULO_GROW_NOISE_GLSL
#define CUMULO_GROW_NOISE_GLSL

uvec2 grow_mul64(uvec2 a, uvec2 b) {  // a * b mod 2^64
  uint hi, lo;
  umulExtended(a.x, b.x, hi, lo);
  hi += a.x * b.y + a.y * b.x;
  return uvec2(lo, hi);
}

uvec2 grow_shr33(uvec2 a) { return uvec2(a.y >> 1u, 0u); }

float grow_lattice(ivec3 p, uvec2 seed) {
  uvec2 h = seed ^ grow_mul64(uvec2(uint(p.x), 0u), uvec2(0x7F4A7C15u, 0x9E3779B9u)) ^
            grow_mul64(uvec2(uint(p.y), 0u), uvec2(0x27D4EB4Fu, 0xC2B2AE3Du)) ^
            grow_mul64(uvec2(uint(p.z), 0u), uvec2(0x9E3779F9u, 0x165667B1u));
  h ^= grow_shr33(h);
  h = grow_mul64(h, uvec2(0xED558CCDu, 0xFF51AFD7u));
  h ^= grow_shr33(h);
  h = grow_mul64(h, uvec2(0x1A85EC53u, 0xC4CEB9FEu));
  h ^= grow_shr33(h);
  return float(h.y >> 8u) * (1.0 / 16777216.0);  // the top 24 bits
}

float grow_value_noise(vec3 p, uvec2 seed) {
  vec3 f = floor(p);
  ivec3 i = ivec3(f);
  vec3 t = p - f;
  t = t * t * (3.0 - 2.0 * t);
  float r = 0.0;
  for (int c = 0; c < 8; ++c) {
    float w = ((c & 1) != 0 ? t.x : 1.0 - t.x) * ((c & 2) != 0 ? t.y : 1.0 - t.y) * ((c & 4) != 0 ? t.z : 1.0 - t.z);
    r += w * grow_lattice(i + ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1), seed);
  }
  return r;
}

#endif
