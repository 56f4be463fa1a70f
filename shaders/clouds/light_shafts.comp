#version 450
// Light shafts, step 1 (2017 talk, seed 001 "Post Processing", after Mitchell's "Volumetric light
// scattering as a post process"): "render a bright highlight around the sun where it is not occluded
// by clouds ... offset this highlight radially away from the sun ... apply a radial blur on this image
// to create the light shafts intensity buffer." Per pixel, samples toward the sun's
// screen position read the occlusion (sky pixel x the voxel clouds' x the 2.5D sky's transmittance)
// weighted by the highlight around the sun and a per-sample decay; the intensity is the unoccluded
// fraction of that weight (1: the sun's light reaches this part of the view's air, 0: cloud or terrain
// shadow it). Quarter resolution (the blurred mask is smooth). light_shafts_apply.comp uses it as the mask of the atmosphere's Mie in-scattering.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "engine/runtime_uniform.glsl"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = SHAFT_BINDING_PARAMS, std140) uniform ShaftBlock { CloudShaftParams S; };
layout(set = 0, binding = SHAFT_BINDING_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = SHAFT_BINDING_CLOUDS) uniform sampler2D clouds_tex;
layout(set = 0, binding = SHAFT_BINDING_SKY) uniform sampler2D sky_tex;
layout(set = 0, binding = SHAFT_BINDING_OUT, r16f) uniform writeonly image2D shafts_out;

vec3 view_dir(vec2 uv) {
  return view_ray_dir(S.inv_view_proj, uv * 2.0 - 1.0, S.camera_pos.xyz);
}

// How much of the sun's highlight this screen point lets through.
float unoccluded_on_screen(vec2 uv) {
  // Terrain shadows the air toward the sun only where it rises to the sun's height in the view (a ridge
  // against a low sun); the ground and the sea below the horizon do not stand in the sun's light.
  if (textureLod(scene_depth, uv, 0.0).r > 0.0) return view_dir(uv).y >= S.sun_dir.y - 0.02 ? 0.0 : 1.0;
  return textureLod(clouds_tex, uv, 0.0).a * textureLod(sky_tex, uv, 0.0).a;
}
// Off screen nothing is known: the border's value, fading to open sky over kOffScreenFade of the screen (uv). Taken
// as open sky at once, a sun off to the side drew a straight edge down the picture where the pixels' rays toward it
// left the screen (the immersed view's ocean: a lighter strip along the left border and a dark box beside it);
// the border's value carried on for good, a cloud at the border hid the sun's glow across the whole side of the sky.
const float kOffScreenFade = 0.25;
float unoccluded(vec2 uv) {
  vec2 inside = clamp(uv, vec2(0.0), vec2(1.0));
  return mix(unoccluded_on_screen(inside), 1.0, smoothstep(0.0, kOffScreenFade, length(uv - inside)));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(shafts_out);
  if (any(greaterThanEqual(pixel, size))) return;
  vec2 uv = (vec2(pixel) + 0.5) / vec2(size);
  int n = runtime_int(S.sun_screen.w);
  // From this pixel a fraction of the way toward the sun (the offset away from the sun: each sample
  // reads the highlight where it lies nearer the sun than the pixel).
  vec2 delta = (S.sun_screen.xy - uv) * S.misc.z / float(n);
  float weight = 0.0, lit = 0.0, decay = 1.0;
  vec2 p = uv;
  for (int i = 0; i < n; ++i) {
    p += delta;
    float mu = dot(view_dir(p), S.sun_dir.xyz);
    float highlight = smoothstep(S.sun_dir.w, 1.0, mu);
    float w = highlight * decay;
    weight += w;
    lit += w * unoccluded(p);
    decay *= S.sun_color.w;
  }
  imageStore(shafts_out, pixel, vec4(weight > 1e-5 ? lit / weight : 1.0, 0.0, 0.0, 0.0));
}
