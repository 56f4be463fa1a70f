// Per-frame parameters of the engine's scene passes (geometry, sky, tonemap), shared by C++ and GLSL.
// Filled by render::FrameRenderer from the extracted FrameSnapshot; one uniform buffer per frame.
#ifndef CUMULO_SHARED_FRAME_PARAMS_H
#define CUMULO_SHARED_FRAME_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

struct FrameParams {
  mat4 view_proj;      // world -> clip (Vulkan clip space, y down, reversed-Z: near 1, far 0)
  mat4 inv_view_proj;  // clip -> world, for sky rays
  vec4 camera_pos;     // xyz: world position (m); w: simulation time (s)
  vec4 sun_dir;        // xyz: unit vector toward the sun; w: sun illuminance scale
  vec4 sun_color;      // rgb: sun colour (linear); w: ambient sky intensity
  vec4 sky_zenith;     // rgb: sky colour straight up; w: fog density (1/m)
  vec4 sky_horizon;    // rgb: sky colour at the horizon; w: fog height falloff (1/m)
  vec4 ground_color;   // rgb: colour below the horizon (ambient bounce); w: exposure
  vec4 viewport;       // width, height, 1/width, 1/height
};
CUMULO_SHARED_SIZE(FrameParams, 240)

// Per-draw push constants of the geometry pass.
struct DrawParams {
  mat4 model;               // object -> world (uniform scale assumed for normals)
  vec4 base_color_factor;   // glTF baseColorFactor (linear)
  vec4 material;            // x: glTF roughness, y: metallic, z: 1 = double-sided, w: unused
};
CUMULO_SHARED_SIZE(DrawParams, 96)

// Push constants of the tonemap pass.
struct TonemapParams {
  vec4 params;  // x: exposure, y: operator (0 = ACES fitted, 1 = Reinhard), z: output is sRGB-encoded by the format (1) or by the shader (0), w: unused
};
CUMULO_SHARED_SIZE(TonemapParams, 16)

CUMULO_SHARED_END

#endif
