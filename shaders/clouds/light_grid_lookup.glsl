// Light grid lookup shared by the march and the shadow map; the includer declares the grid as
// `light_grid_tex` (CLOUD_BINDING_LIGHT_GRID) and includes cloud_common.glsl first.
#include "engine/runtime_uniform.glsl"
#ifndef CUMULO_LIGHT_GRID_LOOKUP_GLSL
#define CUMULO_LIGHT_GRID_LOOKUP_GLSL

// Instance i's (sun, sky, sun within the point's own cloud, own cloud away from the sun) summed density x world
// metres at an asset-space point.
// The grids of all instances are stacked along z in one image (slab i = instance i; a sampler array
// indexed in a loop crashes LLVM 15's lavapipe backend, and one image is one fetch). Outside the box:
// 0 (nothing beyond the cloudscape shadows it); z is clamped to the slab's texel centres so the filter
// never blends two instances.
// Instance i's texture coordinates in an image of such stacked slabs, `depth` texels deep; false outside its box.
bool instance_slab_uvw(int i, vec3 asset_pos, int depth, out vec3 uvw) {
  uvw = asset_uvw(P.instances[i], asset_pos);
  if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0)))) return false;
  float layers = float(depth) / float(P.frame.y);
  uvw.z = (float(i) + clamp(uvw.z, 0.5 / layers, 1.0 - 0.5 / layers)) / float(P.frame.y);
  return true;
}
// Instance i's texel (filtered) of an image stacked that way at an asset-space point; 0 outside its box.
vec4 instance_slab_fetch(sampler3D tex, int i, vec3 asset_pos) {
  vec3 uvw;
  return instance_slab_uvw(i, asset_pos, textureSize(tex, 0).z, uvw) ? textureLod(tex, uvw, 0.0) : vec4(0.0);
}
vec4 light_grid(int i, vec3 asset_pos) { return instance_slab_fetch(light_grid_tex, i, asset_pos); }

// The summed density x world metres that the other instances' clouds put between a world point and the sun (x)
// and the sky straight up (y) (CloudParams::effects.y bit 0; issue 21): instance j's grid holds that sum from each
// voxel of its box to the light, so it is read where the ray from the point toward the light enters j's box (or at
// the point, inside it). The storm cloud and the cloudscape are two instances: without this a low sun lit the storm
// tower through the cloudscape's clouds in front of it.
vec2 other_instances_depth(int i, vec3 world_pos) {
  vec2 sum = vec2(0.0);
  if ((P.effects.y & 1u) == 0u) return sum;
  for (int j = 0; j < runtime_int(P.frame.y); ++j) {  // engine/runtime_uniform.glsl
    if (j == i) continue;
    CloudInstanceParams o = P.instances[j];
    vec3 a = (o.world_to_asset * vec4(world_pos, 1.0)).xyz;
    vec2 s = ray_box(a, o.sun_dir.xyz, o.bounds_min.xyz, o.bounds_max.xyz);
    float t0 = max(s.x, 0.0);
    if (s.y > t0) sum.x += light_grid(j, a + o.sun_dir.xyz * mix(t0, s.y, 1e-3)).x;
    s = ray_box(a, o.sky_dir.xyz, o.bounds_min.xyz, o.bounds_max.xyz);
    t0 = max(s.x, 0.0);
    if (s.y > t0) sum.y += light_grid(j, a + o.sky_dir.xyz * mix(t0, s.y, 1e-3)).y;
  }
  return sum;
}

#endif
