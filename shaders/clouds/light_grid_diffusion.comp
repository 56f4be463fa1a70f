#version 450
// The multiple scattering solved by diffusion on the light grid (issue 21; `--cloud-lighting solve`, the
// CloudSettings::ms_solve flag). The slab lighting guesses the diffused light from the optical depths along the
// sun's line; its level came out right on average but 0.56-2.0x per cloud (bases seen from below too dark, tops
// seen from above too bright, a chamber's walls uneven), because a cloud's shape decides where diffused light
// leaks out. Here the fluence of the scattered light (per unit sun irradiance) is the solution of the diffusion
// equation over the instance's grid,
//   -div(D grad phi) + sigma_a phi = Q,   D = 1 / (3 sigma_tr), sigma_tr = sigma_t (1 - albedo g),
//   sigma_a = sigma_t (1 - albedo),       Q = sigma_s T_sun (the first scattering of the direct sun),
// finite volumes with a face's resistance the two half voxels' h / (2 D) and, where cloud meets air, Marshak's
// vacuum boundary (the fluence falls to zero 2 D beyond the surface: 2 more). Open air is that vacuum (phi = 0);
// air the light grid calls enclosed (a chamber: sky optical depth >= P.sun_dir.w) is solved with the cloud as a
// near-perfect conductor, the integrating sphere of the Stormbird's lair. The march reads phi / 4 pi as the
// multiple scattering's in-scattered radiance (march_render.comp, MS_FIELD).
//
// Solved by tiles: a work group takes 8x8 columns of the grid (every level) into shared memory with the four
// neighbouring columns' strips, relaxes them pc.grid.y times red-black (over-relaxed by pc.grid.x) with the strips
// fixed, and writes them back. The tiles form a checkerboard and one dispatch updates one colour of it, whose strips
// all lie in tiles of the other colour: no tile reads what another writes in the same dispatch. On a CPU device an
// image load costs far more than a shared-memory read; relaxing a tile 8 times per load is what makes the solve
// affordable there (one sweep over the grid with image loads cost ~28 ms per instance on lavapipe).
// pc.region: x instance, y mode (0: the coefficients from the grid and the density, keeping phi (w = 1: the image is
// new, phi starts at 0); 1, 2: the tiles of colour 0 or 1; 3: open air takes its cloud neighbours' fluence, for the
// march's filtering), z layers (z) per instance. Image texel: x Q (1/m), y sigma_t (1/m), z the voxel's kind (0 open
// air, 1 cloud, 2 enclosed air), w phi.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

#define TILE 8
#define SPAN (TILE + 2)
#define MAX_LEVELS 32  // the talk's grid has 32 levels (CloudResources refuses more)

layout(local_size_x = TILE, local_size_y = TILE, local_size_z = 1) in;
layout(set = 0, binding = CLOUD_BINDING_LIGHT_GRID) uniform sampler3D light_grid_tex;
layout(set = 0, binding = CLOUD_BINDING_MS_OUT, rgba16f) uniform image3D ms_field;
layout(push_constant) uniform Push { CloudLightGridPush pc; };
#include "clouds/light_grid_lookup.glsl"

const float kInterface = 2.0;       // Marshak: the extrapolation distance 2 D, in units of D
const float kMinResistance = 0.05;  // enclosed air: nearly free transport, still a finite coefficient

// A tile's columns and its strips: the fluence, and (half floats) the source and the extinction, the extinction
// -1 for open air (0 for enclosed air: no cloud sample in it).
shared float s_phi[SPAN * SPAN * MAX_LEVELS];
shared uint s_coef[SPAN * SPAN * MAX_LEVELS];

float g_mean() { return mix(P.phase.y, P.phase.x, P.phase.z); }

vec4 setup_voxel(CloudInstanceParams inst, int i, ivec3 id, ivec3 size, ivec3 texel, vec4 old) {
  vec3 extent = inst.bounds_max.xyz - inst.bounds_min.xyz;
  vec3 cell = extent / vec3(size);
  vec3 origin = inst.bounds_min.xyz + (vec3(id) + 0.5) * cell;
  vec4 noise = noise_mean();
  // The voxel's mean density from 8 points at its quarter positions (one point would see a 43 m voxel's edge
  // cloud or miss it whole).
  float density = 0.0;
  bool cloud = false;
  for (int k = 0; k < 8; ++k) {
    vec3 o = vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) - 0.5;
    DensitySample s = sample_density_with_noise(CLOUD_ASSET_0, inst, origin + o * 0.5 * cell, noise);
    density += s.full;
    cloud = cloud || s.full > 0.0;
  }
  float sigma_t = density / 8.0 * P.march.x;
  vec4 g = texelFetch(light_grid_tex, texel, 0);
  bool enclosed = P.sun_dir.w > 0.0 && g.y * P.march.x >= P.sun_dir.w;
  float kind = cloud ? 1.0 : enclosed ? 2.0 : 0.0;
  float od = g.x * P.march.x;
  vec3 world = (inverse(inst.world_to_asset) * vec4(origin, 1.0)).xyz;
  od += other_instances_depth(i, world).x * P.march.x;
  return vec4(sigma_t * P.march.y * exp(-od), sigma_t, kind, old.w);
}

int sidx(ivec2 c, int y) { return ((c.y * SPAN) + c.x) * MAX_LEVELS + y; }

// Loads column `c` (tile coordinates, the strips at -1 and TILE) of the grid's column `g` into shared memory.
void load_column(ivec2 c, ivec2 g, ivec3 size, int zbase) {
  bool inside = all(greaterThanEqual(g, ivec2(0))) && all(lessThan(g, size.xz));
  for (int y = 0; y < size.y; ++y) {
    vec4 v = inside ? imageLoad(ms_field, ivec3(g.x, y, g.y + zbase)) : vec4(0.0);  // outside the grid: open air
    s_phi[sidx(c + 1, y)] = v.z == 0.0 ? 0.0 : v.w;  // open air is the vacuum (phi = 0) to the solve
    s_coef[sidx(c + 1, y)] = packHalf2x16(vec2(v.x, v.z == 0.0 ? -1.0 : v.z == 2.0 ? 0.0 : max(v.y, 1e-6)));
  }
}

void main() {
  int layers = int(pc.region.z);
  ivec3 size = ivec3(imageSize(ms_field).xy, layers);
  int i = int(pc.region.x);
  int zbase = i * layers;
  CloudInstanceParams inst = P.instances[i];
  uint mode = pc.region.y;
  if (mode == 0u || mode == 3u) {
    ivec2 col = ivec2(gl_GlobalInvocationID.xy);
    if (col.x >= size.x || col.y >= size.z) return;
    for (int y = 0; y < size.y; ++y) {
      ivec3 id = ivec3(col.x, y, col.y);
      ivec3 texel = id + ivec3(0, 0, zbase);
      vec4 v = imageLoad(ms_field, texel);
      if (mode == 0u) {
        imageStore(ms_field, texel, setup_voxel(inst, i, id, size, texel, pc.region.w != 0u ? vec4(0.0) : v));
        continue;
      }
      if (v.z != 0.0) continue;
      // Open air holds no unknown: it stores its cloud neighbours' mean fluence, so the march's trilinear fetch at a
      // sample within half a voxel of a surface reads the cloud's level there, not half of it (the dark edges'
      // term darkens the last metres by the sample's own depth).
      float beside = 0.0, count = 0.0;
      for (int n = 0; n < 6; ++n) {
        ivec3 d = ivec3(0);
        d[n >> 1] = (n & 1) == 0 ? -1 : 1;
        ivec3 nid = id + d;
        if (any(lessThan(nid, ivec3(0))) || any(greaterThanEqual(nid, size))) continue;
        vec4 o = imageLoad(ms_field, nid + ivec3(0, 0, zbase));
        beside += o.z == 1.0 ? o.w : 0.0;
        count += o.z == 1.0 ? 1.0 : 0.0;
      }
      v.w = count > 0.0 ? beside / count : 0.0;
      imageStore(ms_field, texel, v);
    }
    return;
  }
  // Mode 1 / 2: the tiles of this colour (the whole work group returns together: no thread misses a barrier).
  ivec2 tile = ivec2(gl_WorkGroupID.xy);
  if (((tile.x + tile.y) & 1) != int(mode) - 1) return;
  ivec2 lc = ivec2(gl_LocalInvocationID.xy);
  ivec2 col = tile * TILE + lc;
  load_column(lc, col, size, zbase);
  if (lc.x == 0) load_column(ivec2(-1, lc.y), col - ivec2(1, 0), size, zbase);
  if (lc.x == TILE - 1) load_column(ivec2(TILE, lc.y), col + ivec2(1, 0), size, zbase);
  if (lc.y == 0) load_column(ivec2(lc.x, -1), col - ivec2(0, 1), size, zbase);
  if (lc.y == TILE - 1) load_column(ivec2(lc.x, TILE), col + ivec2(0, 1), size, zbase);
  barrier();
  vec3 cell = (inst.bounds_max.xyz - inst.bounds_min.xyz) / vec3(size) * inst.bounds_min.w;  // world metres
  float tr = 1.0 - P.march.y * g_mean();  // sigma_tr / sigma_t
  float absorb = 1.0 - P.march.y;
  float omega = pc.grid.x;
  bool mine = col.x < size.x && col.y < size.z;
  ivec2 c = lc + 1;
  int sweeps = int(pc.grid.y) * 2;
  for (int k = 0; k < sweeps; ++k) {
    // Red / black by the grid's parity, so a voxel keeps its colour from tile to tile.
    int first = (col.x + col.y + k) & 1;
    for (int y = first; mine && y < size.y; y += 2) {
      int at = sidx(c, y);
      vec2 qs = unpackHalf2x16(s_coef[at]);
      if (qs.y < 0.0) continue;  // open air: no unknown
      bool cloud = qs.y > 0.0;
      float num = qs.x, den = qs.y * absorb;
      for (int n = 0; n < 6; ++n) {
        int axis = n >> 1;
        int step = (n & 1) == 0 ? -1 : 1;
        ivec2 nc = c;
        int ny = y;
        if (axis == 0) nc.x += step;
        else if (axis == 2) nc.y += step;
        else ny += step;
        // Above the top level or below the bottom: open air.
        bool valid = ny >= 0 && ny < size.y;
        int nat = sidx(nc, clamp(ny, 0, size.y - 1));
        vec2 o = valid ? unpackHalf2x16(s_coef[nat]) : vec2(0.0, -1.0);
        float phi = valid ? s_phi[nat] : 0.0;
        float h = cell[axis];
        float r = 1.5 * tr * h * (qs.y + max(o.y, 0.0)) + (cloud != (o.y > 0.0) ? kInterface : 0.0);
        float w = 1.0 / (max(r, kMinResistance) * h);
        num += w * phi;
        den += w;
      }
      s_phi[at] = max(mix(s_phi[at], num / den, omega), 0.0);
    }
    barrier();
  }
  if (!mine) return;
  for (int y = 0; y < size.y; ++y) {
    int at = sidx(c, y);
    if (unpackHalf2x16(s_coef[at]).y < 0.0) continue;
    ivec3 texel = ivec3(col.x, y, col.y + zbase);
    vec4 v = imageLoad(ms_field, texel);
    v.w = s_phi[at];
    imageStore(ms_field, texel, v);
  }
}
