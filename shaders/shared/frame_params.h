// Per-frame parameters of the engine's scene passes (geometry, sky, tonemap), shared by C++ and GLSL.
// Filled by render::FrameRenderer from the extracted FrameSnapshot (camera, sun, SceneLighting); one
// uniform block per frame, also handed to module passes (render::StageContext::frame_params).
#ifndef CUMULO_SHARED_FRAME_PARAMS_H
#define CUMULO_SHARED_FRAME_PARAMS_H
#include "shared/common.h"

// Descriptor bindings of the engine passes (set 0, push descriptors), used by C++ and GLSL alike.
#define FRAME_PARAMS_BINDING 0         // FrameParams uniform block (geometry, sky)
#define GEOMETRY_BASE_COLOR_BINDING 1  // geometry: base-colour texture
#define TONEMAP_HDR_BINDING 0          // tonemap: the HDR scene colour
#define GEOMETRY_LIGHT_SHADOW_BINDING 2  // geometry: the key light's transmittance map (cloud shadows; white when none)
#define GEOMETRY_AERIAL_BINDING 3        // geometry: sampler3D, the atmosphere's aerial-perspective froxels
#define GEOMETRY_NORMAL_BINDING 4        // geometry: a height field's mesh-space shading normals (a 1x1 stand-in when none)

CUMULO_SHARED_BEGIN

#define FRAME_MAX_POINT_LIGHTS 4

struct FrameParams {
  mat4 view_proj;      // world -> clip (Vulkan clip space, y down, reversed-Z: near 1, far 0)
  mat4 inv_view_proj;  // clip -> world, for sky rays
  vec3 camera_position;  // world (m)
  float time_s;          // simulation time (s)
  vec3 sun_direction;    // unit vector toward the sun
  float ambient;         // scale of the hemispheric ambient term
  vec3 sun_radiance;     // sun light reaching the ground (linear, renderer units)
  float exposure;
  vec3 sky_zenith;       // sky colour straight up
  float fog_density;     // 1/m at sea level
  vec3 sky_horizon;      // sky colour at the horizon
  float fog_falloff;     // 1/m, exponential height falloff
  vec3 ground_color;     // below the horizon (ambient bounce)
  float pad0;
  vec2 viewport_size;      // pixels
  vec2 inv_viewport_size;  // 1 / pixels
  // Short-lived point lights on the geometry (a lightning discharge lighting the terrain): xyz world
  // position, w reach (m; the light fades to 0 there); rgb radiance scale at 500 m, w unused.
  vec4 point_light_pos[FRAME_MAX_POINT_LIGHTS];
  vec4 point_light_color[FRAME_MAX_POINT_LIGHTS];
  uvec4 point_light_count;  // x: count
  // The key light's transmittance map (render::LightShadowMap, from a module at Stage::BeforeScene):
  // texel (u, v) holds the transmittance along the light's ray through the point
  // (xy + u / zw.x, misc.x, ..) of a horizontal plane; a point elsewhere is projected onto the plane along the light.
  vec4 shadow_plane;  // xy: world x, z of the map's corner; zw: 1 / its size (m)
  vec4 shadow_misc;   // x: the plane's height (world y); y: 1 = a map is bound; z, w unused
  vec4 aerial;        // x: 1 = aerial perspective from the atmosphere's froxels, 0 = the height fog; y, z, w unused
  // rgb: the sky's irradiance on a horizontal surface / pi (SceneLighting::sky_irradiance): what an upward face's
  // ambient term reflects of the sky (0.5 (zenith + horizon) where the atmosphere does not give it); w: unused
  vec4 sky_irradiance;
};
CUMULO_SHARED_SIZE(FrameParams, 448)
CUMULO_SHARED_OFFSET(FrameParams, sun_radiance, 160)
CUMULO_SHARED_OFFSET(FrameParams, viewport_size, 224)

// Per-draw push constants of the geometry pass.
struct DrawParams {
  mat4 model;               // object -> world (uniform scale assumed for normals)
  vec4 base_color_factor;   // glTF baseColorFactor (linear)
  float roughness;          // glTF roughness
  float metallic;           // glTF metallic
  uint double_sided;        // 1: light both faces
  uint pad0;
  // A height field's shading normals (GEOMETRY_NORMAL_MAP): a mesh-space position p's texture coordinate
  // is (dot(vec4(p, 1), normal_plane_u), dot(vec4(p, 1), normal_plane_v)).
  vec4 normal_plane_u;
  vec4 normal_plane_v;
};
CUMULO_SHARED_SIZE(DrawParams, 128)

// Push constants of the tonemap pass.
#define TONEMAP_ACES 0
#define TONEMAP_REINHARD 1
struct TonemapParams {
  float exposure;
  uint op;           // TONEMAP_ACES or TONEMAP_REINHARD
  uint output_srgb;  // 1: the output format encodes sRGB; 0: the shader encodes it (UNORM targets)
  uint pad0;
};
CUMULO_SHARED_SIZE(TonemapParams, 16)

CUMULO_SHARED_END

#endif
