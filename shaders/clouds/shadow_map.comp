#version 450
// The clouds' shadow on the scene (issue 10): the key light's transmittance through every instance,
// on a horizontal plane at the lowest cloud box's bottom (render::LightShadowMap). Per texel, the
// light's ray from the plane point enters each instance's box; the light grid at the entry holds the
// density summed from there to the box's far side toward the light (what the march's light samples
// read), so T = exp(-extinction x sum over instances). One fetch per instance: the map follows the
// grid's updates (the sun, the instance's transform, density and dissipation).
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_LIGHT_GRID) uniform sampler3D light_grid_tex;
layout(set = 0, binding = CLOUD_BINDING_SHADOW_OUT, r16f) uniform writeonly image2D shadow_out;
layout(push_constant) uniform Push { CloudShadowPush pc; };

#include "clouds/light_grid_lookup.glsl"

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(shadow_out);
  if (any(greaterThanEqual(texel, size))) return;
  vec2 xz = pc.plane.xy + (vec2(texel) + 0.5) / vec2(size) * pc.plane.zw;
  vec3 q = vec3(xz.x, pc.light.w, xz.y);
  vec3 l = normalize(pc.light.xyz);
  float sum = 0.0;
  for (uint k = 0u; k < P.frame.y; ++k) {
    CloudInstanceParams inst = P.instances[k];
    vec3 ao = (inst.world_to_asset * vec4(q, 1.0)).xyz;
    vec3 ad = mat3(inst.world_to_asset) * l;
    vec2 seg = ray_box(ao, ad, inst.bounds_min.xyz, inst.bounds_max.xyz);
    if (seg.y <= max(seg.x, 0.0)) continue;
    // Just inside the box: the grid is 0 outside it.
    float t = max(seg.x, 0.0) + 1e-3 * (seg.y - max(seg.x, 0.0));
    sum += light_grid(int(k), ao + ad * t).x;
  }
  imageStore(shadow_out, texel, vec4(exp(-sum * P.march.x), 0.0, 0.0, 0.0));
}
