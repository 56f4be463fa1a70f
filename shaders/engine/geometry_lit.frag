#version 450
// Geometry pass fragment stage: base colour (texture x factor) lit by the directional sun (Lambert),
// shadowed by the key light's transmittance map (cloud shadows, FrameParams shadow_*), a hemispheric ambient term from the sky and ground colours, short-lived point lights (lightning), and aerial perspective
// (the atmosphere's froxels, or with --aerial-perspective fog exponential height fog toward the sky gradient)
// so the 4 km level fades into the horizon.
// Variants (frame_renderer.cpp): on a CPU device both sides of every branch run, so what a frame does not
// use is compiled out rather than branched around: GEOMETRY_POINT_LIGHTS (a lightning flash lights the
// ground), GEOMETRY_SHADOW_MAP (a feature published the key light's transmittance map), GEOMETRY_AERIAL_LUT
// (the froxels; 0: the height fog), GEOMETRY_NORMAL_MAP (a height field's shading normals from its texture, so
// every level of detail shades as the full mesh: engine/render/height_field_normals.h), GEOMETRY_BASE_TEXTURE
// (0: the material has no base-colour texture, only its factor).
#extension GL_GOOGLE_include_directive : require
#ifndef GEOMETRY_POINT_LIGHTS
#define GEOMETRY_POINT_LIGHTS 1
#endif
#ifndef GEOMETRY_SHADOW_MAP
#define GEOMETRY_SHADOW_MAP 1
#endif
#ifndef GEOMETRY_AERIAL_LUT
#define GEOMETRY_AERIAL_LUT 1
#endif
#ifndef GEOMETRY_NORMAL_MAP
#define GEOMETRY_NORMAL_MAP 0
#endif
#ifndef GEOMETRY_BASE_TEXTURE
#define GEOMETRY_BASE_TEXTURE 1
#endif
#include "engine/sky_common.glsl"
#include "engine/atmosphere_common.glsl"

layout(set = 0, binding = FRAME_PARAMS_BINDING, std140) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = GEOMETRY_BASE_COLOR_BINDING) uniform sampler2D base_color_tex;
layout(set = 0, binding = GEOMETRY_LIGHT_SHADOW_BINDING) uniform sampler2D light_shadow_tex;
layout(set = 0, binding = GEOMETRY_AERIAL_BINDING) uniform sampler3D aerial_tex;
layout(set = 0, binding = GEOMETRY_NORMAL_BINDING) uniform sampler2D normal_tex;
layout(push_constant, std430) uniform DrawBlock { DrawParams draw; };

// Transmittance of the key light at a world point: projected along the light onto the map's plane.
float light_visibility(vec3 p, vec3 l) {
#if GEOMETRY_SHADOW_MAP
  if (frame.shadow_misc.y < 0.5 || l.y < 0.02) return 1.0;
  vec3 q = p + l * ((frame.shadow_misc.x - p.y) / l.y);
  vec2 uv = (q.xz - frame.shadow_plane.xy) * frame.shadow_plane.zw;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  return textureLod(light_shadow_tex, uv, 0.0).r;
#else
  return 1.0;
#endif
}

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec2 in_normal_uv;
layout(location = 0) out vec4 out_color;

void main() {
#if GEOMETRY_BASE_TEXTURE
  vec4 base = texture(base_color_tex, in_uv) * draw.base_color_factor;
#else
  vec4 base = draw.base_color_factor;  // the material has no texture (the ocean)
#endif
#if GEOMETRY_NORMAL_MAP
  vec3 n = normalize(mat3(draw.model) * (texture(normal_tex, in_normal_uv).xyz * 2.0 - 1.0));
#else
  vec3 n = normalize(in_normal);
#endif
  if (!gl_FrontFacing) n = -n;
  vec3 l = frame.sun_direction;
  float ndl = max(dot(n, l), 0.0);
  vec3 sun = frame.sun_radiance * light_visibility(in_world, l);
  // Hemisphere ambient: the sky from above, the ground's bounce from below. An upward face reflects the sky's
  // horizontal irradiance / pi (the cosine weighs the bright band at the horizon little).
  float up = dot(n, kWorldUp) * 0.5 + 0.5;
  vec3 ambient = mix(frame.ground_color, frame.sky_irradiance.rgb, up) * frame.ambient;
  vec3 lit = base.rgb * (sun * ndl + ambient);
  // Point lights (lightning): inverse square, normalized to their colour at 500 m (capped within 100 m),
  // faded to 0 at their reach.
#if GEOMETRY_POINT_LIGHTS
  for (uint i = 0u; i < frame.point_light_count.x; ++i) {
    vec3 to_l = frame.point_light_pos[i].xyz - in_world;
    float d = max(length(to_l), 100.0);
    float fade = clamp(1.0 - d / frame.point_light_pos[i].w, 0.0, 1.0);
    lit += base.rgb * frame.point_light_color[i].rgb * (max(dot(n, to_l / d), 0.0) * 2.5e5 / (d * d) * fade * fade);
  }
#endif

  // Sun glint for smooth materials (the ocean): normalized Blinn-Phong with the exponent from the glTF
  // roughness (alpha = r^2, n = 2/alpha^2 - 2, Walter et al. 2007's mapping) and Schlick Fresnel (F0 0.02).
  vec3 to_cam = frame.camera_position - in_world;
  float dist = length(to_cam);
  vec3 v = to_cam / max(dist, 1e-4);
  float rough = clamp(draw.roughness, 0.05, 1.0);
  float alpha = rough * rough;
  float spec_n = min(2.0 / (alpha * alpha) - 2.0, 2048.0);
  // pow(x, y) is exp2(y log2 x) on a GPU: undefined for x < 0 and for 0^0, and dot(v, h) of two unit vectors
  // rounds past 1 where the camera looks straight away from the sun (a NaN pixel at the antisolar point), hence
  // the clamps: the base in [0, 1], and never 0 where the exponent may be 0 (roughness 1).
  vec3 h = normalize(l + v);
  float fresnel = 0.02 + 0.98 * pow(clamp(1.0 - dot(v, h), 0.0, 1.0), 5.0);
  float spec = (spec_n + 8.0) / 25.1327 * pow(clamp(dot(n, h), 1e-6, 1.0), spec_n) * fresnel * ndl * (1.0 - rough);
  lit += sun * spec;

  vec3 dir = -v;
#if GEOMETRY_AERIAL_LUT
  // Aerial perspective (Hillaire 2020): seen through the air's transmittance, plus its in-scattering.
  vec4 ap = atm_aerial_lookup(aerial_tex, gl_FragCoord.xy * frame.inv_viewport_size, dist * 0.001);
  out_color = vec4(lit * ap.a + ap.rgb, 1.0);
#else
  float fog = fog_amount(frame, dir, dist);
  out_color = vec4(mix(lit, sky_gradient(frame, dir), fog), 1.0);
#endif
}
