// Shared by C++ and GLSL: lets one header declare a GPU parameter block for both languages.
// Rules (std140/std430 and C++ agree only then): members are vec4, uvec4, ivec4 or mat4, or scalars
// packed four at a time with explicit padding; no vec3; each struct's size is static_assert'ed in C++.
// Write CUMULO_SHARED_SIZE(T, bytes) without a trailing semicolon (GLSL rejects a stray one).
#ifndef CUMULO_SHARED_COMMON_H
#define CUMULO_SHARED_COMMON_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace cumulo::shared {
using vec2 = glm::vec2;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = uint32_t;
}  // namespace cumulo::shared
#define CUMULO_SHARED_BEGIN namespace cumulo::shared {
#define CUMULO_SHARED_END }
#define CUMULO_SHARED_SIZE(T, bytes) static_assert(sizeof(T) == (bytes), #T ": C++ and GLSL layouts disagree");
#else
#define CUMULO_SHARED_BEGIN
#define CUMULO_SHARED_END
#define CUMULO_SHARED_SIZE(T, bytes)
#endif

#endif
