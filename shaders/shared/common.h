// Shared by C++ and GLSL: lets one header declare a GPU parameter block for both languages.
// Rules (std140/std430 and C++ agree only then): members are mat4, vec4, uvec4, ivec4; a vec3 only at a
// 16-byte offset and followed by one named 4-byte scalar; vec2 pairs at 8-byte offsets; other scalars
// in named groups of four with explicit padding (never hidden in the .w of an unrelated vector). Each
// struct's size is static_assert'ed in C++ (CUMULO_SHARED_SIZE), and vec3/vec2 members may be pinned
// with CUMULO_SHARED_OFFSET.
// Write CUMULO_SHARED_SIZE(T, bytes) without a trailing semicolon (GLSL rejects a stray one).
#ifndef CUMULO_SHARED_COMMON_H
#define CUMULO_SHARED_COMMON_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
namespace cumulo::shared {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = uint32_t;
}  // namespace cumulo::shared
#define CUMULO_SHARED_BEGIN namespace cumulo::shared {
#define CUMULO_SHARED_END }
#define CUMULO_SHARED_SIZE(T, bytes) static_assert(sizeof(T) == (bytes), #T ": C++ and GLSL layouts disagree");
#define CUMULO_SHARED_OFFSET(T, member, bytes) \
  static_assert(offsetof(T, member) == (bytes), #T "." #member ": C++ and GLSL offsets disagree");
#else
#define CUMULO_SHARED_BEGIN
#define CUMULO_SHARED_END
#define CUMULO_SHARED_SIZE(T, bytes)
#define CUMULO_SHARED_OFFSET(T, member, bytes)
#endif

#endif
