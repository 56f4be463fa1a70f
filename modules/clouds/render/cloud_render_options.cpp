#include "modules/clouds/render/cloud_render_options.h"

namespace cumulo::clouds::render {

CloudSettings cloud_settings(const CloudRenderOptions& o) {
  CloudSettings s;
  s.ablation = o.ablation;
  s.debug = o.debug;
  s.temporal = o.temporal;
  s.light_grid_method = o.light_grid_method;
  s.light_sample_noise_mean = o.light_sample_noise_mean;
  s.lights = o.lights;
  s.light_grid_always_update = o.light_grid_always_update;
  s.reprojection_block = o.reprojection_block;
  s.near_reprojection_block = o.near_reprojection_block;
  s.animated_jitter_distance_m = o.talk_jitter ? kTalkAnimatedJitterDistanceM : kJitterAnimatedEverywhereM;
  s.shadows = o.shadows;
  s.terrain_shadow = o.terrain_shadow;
  s.effects = o.effects;
  apply_lighting_preset(s, o.lighting);
  if (o.ms_strength >= 0.0f) s.ms_strength = o.ms_strength;
  if (o.ambient_occlusion >= 0.0f) s.ambient_occlusion_scale = o.ambient_occlusion;
  if (o.ms_attenuation_inside >= 0.0f) s.ms_attenuation_inside = o.ms_attenuation_inside;
  if (o.ms_other_clouds >= 0.0f) s.ms_other_cloud_attenuation = o.ms_other_clouds;
  if (o.ms_enclosed >= 0.0f) s.ms_enclosed_sky_depth = o.ms_enclosed;
  if (o.ground_albedo >= 0.0f) s.ground_albedo = o.ground_albedo;
  if (o.ms_anisotropy >= 0.0f) s.ms_anisotropy = o.ms_anisotropy;
  if (o.ms_incidence >= 0.0f) s.ms_incidence = o.ms_incidence;
  if (o.ms_cavity >= 0.0f) s.ms_cavity = o.ms_cavity;
  if (o.sky_side >= 0.0f) s.sky_side = o.sky_side;
  if (o.ms_forward >= 0.0f) s.ms_forward = o.ms_forward;
  if (o.envelope_ms_diffused >= 0.0f) s.envelope_ms_diffused = o.envelope_ms_diffused;
  if (o.envelope_eccentricity >= 0.0f) s.envelope_eccentricity = o.envelope_eccentricity;
  if (o.envelope_light_erosion) s.envelope_light_erosion = *o.envelope_light_erosion;
  if (o.light_sample_m > 0.0f) s.light_sample_m = o.light_sample_m;
  if (o.light_samples > 0) s.light_samples = uint32_t(o.light_samples);
  if (o.light_sample_growth > 0.0f) s.light_sample_growth = o.light_sample_growth;
  if (o.edge_depth >= 0.0f) s.edge_depth_scale = o.edge_depth;
  if (o.ms_lateral >= 0.0f) s.ms_lateral = o.ms_lateral;
  if (o.ms_solve_iterations >= 0) s.ms_solve_iterations = uint32_t(o.ms_solve_iterations);
  if (o.ms_solve_local > 0) s.ms_solve_local_iterations = uint32_t(o.ms_solve_local);
  if (o.ms_solve_weight >= 0.0f) s.ms_solve_weight = o.ms_solve_weight;
  if (o.ms_solve_strength >= 0.0f) s.ms_solve_strength = o.ms_solve_strength;
  if (o.ms_solve_omega > 0.0f) s.ms_solve_omega = o.ms_solve_omega;
  if (o.step_growth >= 1.0f) s.step_growth = o.step_growth;
  if (o.sky_mean) s.sky_mean_ambient = *o.sky_mean;
  if (o.sky_hue) s.sky_mean_hue = *o.sky_hue;
  if (o.instance_shadows) s.instance_shadows = *o.instance_shadows;
  return s;
}

float split_distance_for_device(const CloudRenderOptions& o, bool cpu_device) {
  if (o.split_distance_m > 0.0f) return o.split_distance_m;
  return cpu_device ? kCpuSplitDistanceM : CloudSettings{}.split_distance_m;
}

int growth_update_frames_for_device(const CloudRenderOptions& o, bool cpu_device) {
  if (o.growth_update_frames > 0) return o.growth_update_frames;
  return cpu_device ? 8 : 4;
}

}  // namespace cumulo::clouds::render
