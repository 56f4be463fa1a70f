// Light grid lookup shared by the march and the shadow map; the includer declares the grid as
// `light_grid_tex` (CLOUD_BINDING_LIGHT_GRID) and includes cloud_common.glsl first.
#ifndef CUMULO_LIGHT_GRID_LOOKUP_GLSL
#define CUMULO_LIGHT_GRID_LOOKUP_GLSL

// Instance i's (sun, sky, sun within the point's own cloud, own cloud away from the sun) summed density x world
// metres at an asset-space point.
// The grids of all instances are stacked along z in one image (slab i = instance i; a sampler array
// indexed in a loop crashes LLVM 15's lavapipe backend, and one image is one fetch). Outside the box:
// 0 (nothing beyond the cloudscape shadows it); z is clamped to the slab's texel centres so the filter
// never blends two instances.
vec4 light_grid(int i, vec3 asset_pos) {
  vec3 uvw = asset_uvw(P.instances[i], asset_pos);
  if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0)))) return vec4(0.0);
  float layers = float(textureSize(light_grid_tex, 0).z) / float(P.frame.y);
  uvw.z = (float(i) + clamp(uvw.z, 0.5 / layers, 1.0 - 0.5 / layers)) / float(P.frame.y);
  return textureLod(light_grid_tex, uvw, 0.0);
}

#endif
