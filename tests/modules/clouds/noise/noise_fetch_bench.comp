#version 460
// clouds/noise fetch benchmark: each invocation marches a straight ray through the tiling voxel noise
// (repeat addressing, trilinear, explicit LOD as the 2023 up-rez sampler does) and sums the samples,
// so the cost is dominated by 3D texture fetches of the format under test.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform sampler3D noise_tex;
layout(set = 0, binding = 1, std430) buffer Results { vec4 results[]; };
layout(push_constant) uniform Params {
  uint steps;      // fetches per invocation (from a push constant so the loop is not unrolled)
  float step_uvw;  // step length in texture space
  float lod;
  uint pad;
} params;

uint hash(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return x;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  vec3 p = vec3(hash(i), hash(i ^ 0x68e31da4u), hash(i ^ 0xb5297a4du)) / 4294967296.0;
  vec3 d = normalize(vec3(hash(i * 3u + 1u), hash(i * 3u + 2u), hash(i * 3u + 3u)) / 4294967296.0 - 0.5);
  vec4 sum = vec4(0.0);
  for (uint s = 0u; s < params.steps; ++s) {
    sum += textureLod(noise_tex, p, params.lod);
    p += d * params.step_uvw;
  }
  results[i] = sum;
}
