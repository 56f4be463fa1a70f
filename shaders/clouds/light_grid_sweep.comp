#version 450
// The light grid by a sweep (an improvement on the talk's per-voxel rays, light_grid_update.comp; the
// faithful form stays reachable with CloudSettings::light_grid_method = Rays, --cloud-light-grid-method rays).
//
// The talk marches a ray from every voxel to the grid boundary: O(voxels x ray length). Rays toward a
// directional light are parallel, so the sum from a voxel is the sum over its own stretch up to the next
// level of the grid plus the sum already computed at the point where the ray crosses that level:
//   S(v) = integral of density over [v, v + d * delta] + S(level above, bilinear at v + d * delta)
// with delta = level height / |d.y|. One dispatch per level, from the level nearest the light down
// (a barrier between levels), each voxel samples density a few times (delta / voxel, at most
// pc.grid.x) instead of marching the whole ray: O(voxels). The light direction's slope is clamped
// to kMinSlope so a sun on the horizon still reaches the next level (delta <= level / kMinSlope).
// Where the ray leaves the box before the next level, the sum ends there (nothing outside shadows it),
// as in the talk. A voxel with no cloud near it (the field NVDF says so) costs one fetch.
// Amortized by levels rather than slabs: each frame continues the sweep by 1/8 of the levels over the
// whole grid (a level reads the one nearer the light, updated this frame or in an earlier one), so a
// frame has few dispatches (on lavapipe each dispatch + barrier costs about 0.2 ms even when empty).
// Values and units as light_grid_update.comp: x = summed density toward the sun, y = toward the sky,
// z = the part of x in the voxel's own cloud, w = the own cloud's summed density away from the sun (its sweep
// runs from the level farthest from the sun), density x world metres, from the voxel centre.
// pc.region: x instance, y first z layer, z layer count (the instance's whole grid), w the level (y) written;
// pc.grid: x most density samples per stretch, y channels updated (bits: 1 sun, 2 sky, 4 away from the sun; a
// channel not updated keeps its value), z z layers per instance.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

layout(local_size_x = 8, local_size_y = 1, local_size_z = 8) in;
layout(set = 0, binding = CLOUD_BINDING_GRID_OUT, rgba16f) uniform image3D grid;
layout(push_constant) uniform Push { CloudLightGridPush pc; };

const float kMinSlope = 0.05;  // about 3 degrees above the horizon

// Level `y` of the slab stack at continuous texel coordinates `xz` (texel centres at +0.5), bilinear.
vec4 level_value(int y, vec2 xz, ivec2 size_xz, int zbase) {
  vec2 f = xz - 0.5;
  ivec2 b = ivec2(floor(f));
  vec2 w = f - vec2(b);
  ivec2 lo = clamp(b, ivec2(0), size_xz - 1), hi = clamp(b + 1, ivec2(0), size_xz - 1);
  vec4 v00 = imageLoad(grid, ivec3(lo.x, y, zbase + lo.y));
  vec4 v10 = imageLoad(grid, ivec3(hi.x, y, zbase + lo.y));
  vec4 v01 = imageLoad(grid, ivec3(lo.x, y, zbase + hi.y));
  vec4 v11 = imageLoad(grid, ivec3(hi.x, y, zbase + hi.y));
  return mix(mix(v00, v10, w.x), mix(v01, v11, w.x), w.y);
}

// Summed density (asset metres) from `origin` toward `dir`, given the level above/below it is done:
// x the whole sum, y the part of it in the cloud the voxel is in (its "own" cloud: the sum up to the first
// sample outside every cloud's profile, where the light leaves one cloud for the air between clouds; issue 21,
// the march lets diffused light cross a cloud but not the gap to another). `channel` 0 reads the sun sums of
// the next level (x total, z own), 1 the sky sums (y; no own part), 2 the own sums away from the sun (w; only
// the own part is kept, so a voxel in air samples nothing).
// Air under a sky optical depth of P.sun_dir.w or more is inside a cloud (a chamber): the own cloud goes on across
// it (0: the own cloud ends at the first air). `sky`: summed density x world metres straight up.
bool enclosed(float sky) { return P.sun_dir.w > 0.0 && sky * P.march.x >= P.sun_dir.w; }

// `enclosed_here`: the voxel is in enclosed air (see enclosed()).
vec2 sweep(CloudInstanceParams inst, vec3 origin, vec3 dir, int y, int layers_y, vec3 cell, ivec2 size_xz, int zbase,
           float voxel, vec4 noise, float clear, int channel, bool enclosed_here) {
  float slope = max(abs(dir.y), kMinSlope);
  float up = dir.y >= 0.0 ? 1.0 : -1.0;
  vec3 d = normalize(vec3(dir.x, up * slope, dir.z));
  float delta = cell.y / abs(d.y);
  vec2 seg = ray_box(origin, d, inst.bounds_min.xyz, inst.bounds_max.xyz);
  float t_exit = max(seg.y, 0.0);
  float len = min(delta, t_exit);
  // `clear`: no cloud within this distance of the voxel centre, so a shorter stretch needs no samples.
  // A voxel in air has no cloud of its own, unless the air is enclosed (a chamber's).
  bool in_own = clear <= 0.0 || enclosed_here;
  int k = clear > len || (channel == 2 && !in_own) ? 0 : clamp(int(ceil(len / voxel)), 1, int(pc.grid.x));
  float sum = 0.0, own = 0.0;
  // The next level's sums where the stretch reaches it (its sky sum decides whether air on the way is enclosed).
  int next = y + int(up);
  bool has_next = delta < t_exit && next >= 0 && next < layers_y;
  vec4 v = vec4(0.0);
  if (has_next) {
    vec3 pn = origin + d * delta;
    v = level_value(next, (pn.xz - inst.bounds_min.xz) / cell.xz, size_xz, zbase) / inst.bounds_min.w;  // stored in world metres
  }
  bool air_enclosed = enclosed(v.y * inst.bounds_min.w);
  for (int j = 0; j < k; ++j) {
    DensitySample s = sample_density_with_noise(CLOUD_ASSET_0, inst, origin + d * ((float(j) + 0.5) / float(k) * len), noise);
    in_own = in_own && (s.raw_profile > 0.0 || air_enclosed);
    sum += s.full;
    own += in_own ? s.full : 0.0;
  }
  float w = len / float(max(k, 1));
  sum *= w, own *= w;
  if (has_next) {
    sum += channel == 0 ? v.x : v.y;
    if (k == 0) in_own = in_own && air_enclosed;  // no sample: the stretch is air
    if (in_own && channel != 1) own += channel == 0 ? v.z : v.w;
  }
  return vec2(sum, own);
}

void main() {
  int layers = int(pc.grid.z);
  ivec3 size = ivec3(imageSize(grid).xy, layers);
  if (gl_GlobalInvocationID.x >= uint(size.x) || gl_GlobalInvocationID.z >= pc.region.z) return;
  int y = int(pc.region.w);
  ivec3 id = ivec3(gl_GlobalInvocationID.x, y, int(gl_GlobalInvocationID.z + pc.region.y));
  if (id.z >= layers) return;
  int zbase = int(pc.region.x) * layers;
  CloudInstanceParams inst = P.instances[pc.region.x];
  vec3 extent = inst.bounds_max.xyz - inst.bounds_min.xyz;
  vec3 cell = extent / vec3(size);
  vec3 origin = inst.bounds_min.xyz + (vec3(id) + 0.5) * cell;
  float voxel = min(cell.x, min(cell.y, cell.z));
  // The noise at this voxel's scale: the grid cannot hold detail finer than its voxel (16-32 m, several
  // times the 100 m tile's mip whose texel is a voxel would alias at this spacing), so the noise enters
  // by its mean, the last mip's single texel: one fetch per voxel instead of a trilinear fetch per sample.
  // (light_grid_update.comp, the talk's rays, samples the noise at the voxel's mip.)
  vec4 noise = noise_mean();
  ivec3 texel = id + ivec3(0, 0, zbase);
  // Empty air costs one fetch for both channels: the signed distance at the voxel centre, less one field
  // texel for the filtering between texels, is a radius free of cloud.
  float margin = (inst.bounds_max.x - inst.bounds_min.x) / float(textureSize(field_tex, 0).x);
  float clear = cloud_distance(field_tex, asset_uvw(inst, origin)) - margin;
  uint channels = uint(pc.grid.y);
  vec4 value = imageLoad(grid, texel);  // channels not updated keep their values (no dispatch updates all four)
  // The sky first: whether this voxel's air is enclosed reads it.
  if ((channels & 2u) != 0u)
    value.y = sweep(inst, origin, inst.sky_dir.xyz, y, size.y, cell, size.xz, zbase, voxel, noise, clear, 1, false).x * inst.bounds_min.w;
  bool here = enclosed(value.y);
  if ((channels & 1u) != 0u)
    value.xz = sweep(inst, origin, inst.sun_dir.xyz, y, size.y, cell, size.xz, zbase, voxel, noise, clear, 0, here) * inst.bounds_min.w;
  if ((channels & 4u) != 0u)
    value.w = sweep(inst, origin, -inst.sun_dir.xyz, y, size.y, cell, size.xz, zbase, voxel, noise, clear, 2, here).y * inst.bounds_min.w;
  imageStore(grid, texel, value);
}
