#pragma once
// 64-bit FNV-1a: stable across runs and machines, used for cache keys (shaders, pipelines) and
// volume checksums. Not cryptographic.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace cumulo {

constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;

constexpr uint64_t hash64(const void* data, size_t size, uint64_t seed = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t h = seed;
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}

inline uint64_t hash64(std::string_view s, uint64_t seed = kFnvOffset) { return hash64(s.data(), s.size(), seed); }
// A string literal with a seed: without this, hash64("name", seed) would pick the (data, size) form above
// and read `seed` bytes of the literal.
template <size_t N>
inline uint64_t hash64(const char (&s)[N], uint64_t seed = kFnvOffset) {
  return hash64(std::string_view(s, N - 1), seed);
}

inline uint64_t hash_combine(uint64_t a, uint64_t b) { return a ^ (b + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2)); }

}  // namespace cumulo
