#version 450
// Geometry pass fragment stage: base colour (texture x factor) lit by the directional sun (Lambert),
// a hemispheric ambient term from the sky and ground colours, and exponential height fog toward the sky
// gradient (aerial perspective) so the 4 km level fades into the horizon.
#extension GL_GOOGLE_include_directive : require
#include "engine/sky_common.glsl"

layout(set = 0, binding = 0, std140) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = 1) uniform sampler2D base_color_tex;
layout(push_constant, std430) uniform DrawBlock { DrawParams draw; };

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() {
  vec4 base = texture(base_color_tex, in_uv) * draw.base_color_factor;
  vec3 n = normalize(in_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 l = frame.sun_dir.xyz;
  float ndl = max(dot(n, l), 0.0);
  // Hemisphere ambient: sky colour from above, ground bounce from below.
  float up = dot(n, kWorldUp) * 0.5 + 0.5;
  vec3 ambient = mix(frame.ground_color.rgb, mix(frame.sky_horizon.rgb, frame.sky_zenith.rgb, 0.5), up) * frame.sun_color.w;
  vec3 lit = base.rgb * (frame.sun_color.rgb * frame.sun_dir.w * ndl + ambient);

  // Water and wet sand: a little sun glint where the surface is smooth (alpha of the factor < 1 is not
  // used by glTF opaque materials, so a blue-dominant, flat surface is the cue here).
  vec3 to_cam = frame.camera_pos.xyz - in_world;
  float dist = length(to_cam);
  vec3 v = to_cam / max(dist, 1e-4);
  float water = step(base.r + 0.05, base.b) * step(0.9, n.y);
  vec3 h = normalize(l + v);
  lit += water * frame.sun_color.rgb * frame.sun_dir.w * pow(max(dot(n, h), 0.0), 200.0) * 2.0;

  vec3 dir = -v;
  float fog = fog_amount(frame, dir, dist);
  out_color = vec4(mix(lit, sky_gradient(frame, dir), fog), 1.0);
}
