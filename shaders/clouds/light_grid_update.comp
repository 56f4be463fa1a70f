#version 450
// Voxel cloud lighting: the light grid (2023 talk, seed 000 "Lighting": "the remaining samples are
// pre-computed in a separate pass and stored in a 256x256x32 voxel grid ... If a voxel has cloud in it,
// then a ray is marched between that voxel and the boundaries of the voxel grid and density is
// accumulated at each step ... amortized over 8 frames"; "When we pre-calculate summed density along
// the ray toward the sky, we get a result that can be used to scale this ambient scattering").
//
// One dispatch updates a slab of z layers of one instance's grid (the C++ side picks one eighth per
// frame, or all of it on a rebuild). Per voxel centre, two rays in asset space: toward the sun and
// straight up, to the asset box boundary. They are sphere-traced by the field NVDF (step = max(SDF,
// one grid voxel)) so empty air costs few steps, and density is summed only where the SDF is
// negative. Stored: x = summed density toward the sun, y = toward the sky, z = the part of x in the voxel's
// own cloud (up to the first step in air), w = the own cloud's summed density away from the sun, in density x
// world metres
// (the march multiplies by the extinction coefficient). Every voxel is computed, not only cloudy ones:
// the march reads the grid 2 light samples away from its sample, often in the air between clouds,
// which is what gives the long inter-cloud shadows.
// Density is the up-rez without the near-camera details, at the noise mip whose texel matches the grid
// voxel (the grid cannot hold finer detail).
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(set = 0, binding = CLOUD_BINDING_GRID_OUT, rgba16f) uniform writeonly image3D grid_out;
layout(push_constant) uniform Push { CloudLightGridPush pc; };

// x: the summed density (world metres) from `origin` along `dir` to the box; y: its part in the cloud the
// voxel is in, up to the first step in air (light_grid_sweep.comp says why).
// `own_only`: stop at the own cloud's end (the sum beyond is not wanted).
vec2 summed_density(CloudInstanceParams inst, vec3 origin, vec3 dir, float voxel, float mip, uint max_steps, bool own_only) {
  vec2 seg = ray_box(origin, dir, inst.bounds_min.xyz, inst.bounds_max.xyz);
  float t_exit = max(seg.y, 0.0);
  float sum = 0.0, own = 0.0;
  // (Enclosed air, the slab lighting's chamber rule, needs the sky sums of the points on the way: only the sweep
  // has them; here the own cloud ends at the first air.)
  bool in_own = cloud_distance(field_tex, asset_uvw(inst, origin)) <= 0.0;
  float t = 0.5 * voxel;  // the voxel's own half: the march's first light samples cover the rest near it
  for (uint s = 0u; s < max_steps; ++s) {
    if (t >= t_exit) break;
    vec3 p = origin + dir * t;
    vec3 uvw = asset_uvw(inst, p);
    float sdf = cloud_distance(field_tex, uvw);
    float step_len = max(sdf, voxel);
    in_own = in_own && sdf <= 0.0;
    CLOUD_WHERE(sdf < 0.0) {
      DensitySample ds = sample_density(CLOUD_ASSET_0, inst, p, 1e4, mip, false);
      in_own = in_own && ds.raw_profile > 0.0;
      float v = ds.full * min(step_len, t_exit - t);
      sum += v;
      own += in_own ? v : 0.0;
    }
    t += step_len;
    if (own_only && !in_own) break;
  }
  return vec2(sum, own) * inst.bounds_min.w;  // asset metres -> world metres
}

void main() {
  // The image stacks every instance's grid along z: this instance's slab starts at region.x * layers.
  int layers = int(pc.grid.z);
  ivec3 size = ivec3(imageSize(grid_out).xy, layers);
  ivec3 id = ivec3(gl_GlobalInvocationID) + ivec3(0, 0, int(pc.region.y));
  if (any(greaterThanEqual(id, size)) || gl_GlobalInvocationID.z >= pc.region.z) return;
  CloudInstanceParams inst = P.instances[pc.region.x];
  vec3 extent = inst.bounds_max.xyz - inst.bounds_min.xyz;
  vec3 cell = extent / vec3(size);
  vec3 origin = inst.bounds_min.xyz + (vec3(id) + 0.5) * cell;
  float voxel = min(cell.x, min(cell.y, cell.z));
  // Noise texel is 100 m / noise size; pick the mip whose texel is about one grid voxel.
  float noise_texel = 100.0 / float(textureSize(noise_tex, 0).x);
  float mip = max(0.0, log2(voxel / noise_texel));
  vec2 sun = summed_density(inst, origin, inst.sun_dir.xyz, voxel, mip, uint(pc.grid.x), false);
  float sky = summed_density(inst, origin, inst.sky_dir.xyz, voxel, mip, uint(pc.grid.y), false).x;
  float away = summed_density(inst, origin, -inst.sun_dir.xyz, voxel, mip, uint(pc.grid.x), true).y;
  imageStore(grid_out, id + ivec3(0, 0, int(pc.region.x) * layers), vec4(sun.x, sky, sun.y, away));
}
