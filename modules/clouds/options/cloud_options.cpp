#include "modules/clouds/options/cloud_options.h"

#include <array>

#include "engine/core/args.h"
#include "engine/core/enum_names.h"
#include "engine/core/error.h"

namespace cumulo::clouds {
namespace {

using render::CloudRenderOptions;

// --cloud-reprojection: 1 of N pixels, stored as the block's side (CloudSettings::reprojection_block).
constexpr std::array kReprojectionNames{EnumName<uint32_t>{0, "auto"}, EnumName<uint32_t>{1, "1"},
                                        EnumName<uint32_t>{2, "4"}, EnumName<uint32_t>{4, "16"}};
constexpr std::array kNearReprojectionNames{EnumName<uint32_t>{1, "1"}, EnumName<uint32_t>{2, "4"},
                                            EnumName<uint32_t>{4, "16"}};
constexpr std::array kLightGridNames{EnumName<bool>{true, "talk"}, EnumName<bool>{false, "device"}};
constexpr std::array kJitterNames{EnumName<bool>{false, "animated"}, EnumName<bool>{true, "talk"}};
constexpr std::array kEnvelopeSteppingNames{EnumName<bool>{true, "cone"}, EnumName<bool>{false, "fixed"}};
constexpr std::array kLightSampleNoiseNames{EnumName<bool>{true, "mean"}, EnumName<bool>{false, "sampled"}};

void add_pass_options(ArgParser& p, CloudRenderOptions& o) {
  p.on_off("--clouds", "draw the cloud module's passes (default on)", &o.enabled)
      .choice("--cloud-debug", render::kCloudDebugViewNames, "cloud debug view (default none)", &o.debug)
      .option("--cloud-formats", names_choice(render::kCloudFormatSetNames),
              "cloud GPU formats: compressed (BC1) or uncompressed (RGBA8 + R16); default by device",
              [&o](const std::string& s) { o.formats = parse_name_or_fail(render::kCloudFormatSetNames, "--cloud-formats", s); })
      .choice("--cloud-ablation", render::kCloudAblationNames,
              "cloud march variant of the talk's cost table: base, voxel-lighting, full (default)", &o.ablation)
      .on_off("--cloud-temporal", "temporal accumulation of the jittered cloud march (default on)", &o.temporal)
      .choice("--cloud-reprojection", kReprojectionNames,
              "march 1 of N pixels per frame and reproject the rest (with temporal on): 1 every pixel, 4, 16 as in "
              "the 2015 talk, auto (default: 4 at 30 Hz, 16 for the 40/60 Hz far segment)",
              &o.reprojection_block)
      .choice("--cloud-near-reprojection", kNearReprojectionNames,
              "the 40/60 Hz near segment (half resolution) marches 1 of N of its pixels per frame and reprojects the "
              "rest (with temporal on): 1 every pixel, 4, 16 (default)",
              &o.near_reprojection_block)
      .choice("--cloud-jitter", kJitterNames,
              "the march's jitter: animated every frame at every distance (default; the temporal accumulation averages "
              "it), or as in the talk, animated within 250 m and static beyond",
              &o.talk_jitter)
      .choice("--cloud-light-grid", kLightGridNames, "auto",
              "light grid size: the talk's 256x256x32, or sized for the device, 96x96x16 on CPU devices (default auto: the "
              "device's; cumulo fidelity the talk's)",
              &o.talk_light_grid)
      .option("--cloud-light-grid-samples", "N",
              "the sweep's most density samples along one voxel's stretch to the next level of the light grid (a low "
              "sun's stretch crosses many voxels; default: the device's)",
              &o.light_grid_samples)
      .range(1.0, 256.0)
      .choice("--cloud-light-grid-method", render::kCloudLightGridMethodNames,
              "light grid computation: the talk's ray from every voxel, or a sweep level by level from the light "
              "(default; the same sums at a fraction of the cost)",
              &o.light_grid_method)
      .choice("--cloud-light-sample-noise", kLightSampleNoiseNames,
              "noise in the two marched light samples: its mean (default), or sampled as in the talk",
              &o.light_sample_noise_mean)
      .choice("--cloud-lights", render::kCloudLightsNames,
              "which lights reach the clouds: all (default), the sun alone or the sky alone (cumulo fidelity traces its "
              "reference with the same one, to measure each source's share of the lighting model)",
              &o.lights)
      .on_off("--cloud-shadows", "the clouds' shadow on the terrain and the ocean (default on)", &o.shadows)
      .on_off("--cloud-terrain-shadow", "the terrain's shadow on the clouds (default on)", &o.terrain_shadow)
      .on_off("--cloud-light-shafts", "light shafts through gaps in the clouds (default on)", &o.light_shafts)
      .on_off("--cloud-rain", "the rain columns under precipitating clouds (default on)", &o.rain)
      .choice("--cloud-sky", kOnOffNames, "auto",
              "the weather-driven 2.5D sky beyond and above the voxel cloudscape (default auto: on with a WeatherScheduler)",
              &o.sky)
      .choice("--envelope", kOnOffNames, "auto",
              "the Envelope method's orographic clouds (default auto: on in a level with OrographicClouds)", &o.envelope)
      .choice("--envelope-stepping", kEnvelopeSteppingNames,
              "the envelope clouds' sample placement: cone and distance step mapping (default), or fixed steps (the "
              "talk's before)",
              &o.envelope_cone_stepping)
      .choice("--envelope-reprojection", kReprojectionNames,
              "the envelope clouds' far pass marches 1 of N pixels per frame and reprojects the rest: 1 every pixel (the "
              "talk's way), 4, 16, auto (default: 1 on a GPU; on a CPU device 4 at 30 Hz, 16 for the 40/60 Hz far pass)",
              &o.envelope_block)
      .option("--cloud-growth-steps-per-frame", "N",
              "a growing cloud (CloudGrowth) takes at most N simulation steps a frame toward where its component says it "
              "should be (default 1; 0: the clouds do not grow)",
              &o.growth_steps_per_frame)
      .range(0.0, 64.0)
      .on_off("--cloud-growth-spread",
              "a growing cloud's images and light grid are rebuilt in the frame after its steps, not the same one, so "
              "no frame pays for both (default on)",
              &o.growth_spread)
      .option("--cloud-growth-update-frames", "N",
              "with the spread, a growing cloud's images are updated over N frames: the distance field and the "
              "attributes in the first N - 1, the images in the last; no step meanwhile (default 0: by device, 4 on "
              "a GPU, 8 on a CPU device; 1: the whole update in one frame)",
              &o.growth_update_frames)
      .range(0.0, 32.0)
      .on_off("--cloud-growth-light-sweep",
              "a growing cloud's new images are swept into its light grid over the next frames (the sweep's cycle, from "
              "the level nearest the sun) instead of rebuilding the grid in the update's last frame (default off: the "
              "gradual change shows the temporal reprojection's pattern over the growing cloud; with "
              "--cloud-light-grid-method sweep)",
              &o.growth_light_sweep)
      .on_off("--cloud-sky-occlusion",
              "the 2.5D sky is not marched where this frame's voxel clouds hide it (it keeps its last value; default on)",
              &o.sky_occlusion)
      .option("--cloud-effects-off", "LIST",
              "switch off lighting effects of the talks in the march, comma-separated: silver-lining, dark-edges, "
              "inner-glow, long-shadows, ambient-direction, lightning-glow (default: all on)",
              [&o](const std::string& list) {
                o.effects = CLOUD_EFFECTS_ALL;
                for (size_t b = 0; b < list.size();) {
                  size_t e = list.find(',', b);
                  if (e == std::string::npos) e = list.size();
                  const std::string name = list.substr(b, e - b);
                  const uint32_t bit = render::cloud_effect_bit(name);
                  if (!name.empty() && !bit)
                    fail("--cloud-effects-off: unknown effect \"%s\" (expected silver-lining, dark-edges, inner-glow, "
                         "long-shadows, ambient-direction or lightning-glow)", name.c_str());
                  o.effects &= ~bit;
                  b = e + 1;
                }
              });
}

void add_lighting_options(ArgParser& p, CloudRenderOptions& o) {
  p.choice("--cloud-lighting", render::kCloudLightingPresetNames,
           "the lighting model: the talks' constants, the set tuned against the path-traced reference "
           "(cumulo fidelity), diffusion's falloff of the multiple scattering through a cloud and Beer-Lambert "
           "across other clouds, or the slab (default; issue 21): a slab's falloff from the cloud's depth on both "
           "sides along the sun's line, enclosed air (a chamber) inside the cloud, the sky from the upper "
           "hemisphere, its diffused light, a ground bounce and a forward lobe of the multiple scattering; or the solve: "
           "the slab's terms with the multiple scattering solved by diffusion on the light grid",
           &o.lighting)
      .option("--cloud-ms-strength", "X", "the multiple-scattering field's strength, overriding the preset's (talk: 1)",
              &o.ms_strength)
      .range(0.0, 100.0)
      .option("--cloud-ambient-occlusion", "X",
              "the scale of the summed sky density on the ambient, overriding the preset's (talk: 0.1)",
              &o.ambient_occlusion)
      .range(0.0, 100.0)
      .option("--cloud-ms-attenuation-inside", "X",
              "the multiple-scattering field's attenuation deep inside a cloud toward the sun (the inner glow's "
              "relaxation), overriding the preset's (talk: 0.05)",
              &o.ms_attenuation_inside)
      .range(0.0, 10.0)
      .option("--cloud-ms-other-clouds", "X",
              "with the diffusion lighting, the Beer-Lambert coefficient of other clouds' optical depth on the multiple "
              "scattering, overriding the preset's (diffusion: 1; 0: other clouds shadow it as its own cloud does)",
              &o.ms_other_clouds)
      .range(0.0, 10.0)
      .option("--cloud-ms-enclosed", "X",
              "with the diffusion lighting, the own cloud goes on across air under at least this sky optical depth (a "
              "chamber inside a cloud), overriding the preset's (slab: 3; 0: it ends at the first air toward the sun)",
              &o.ms_enclosed)
      .range(0.0, 1000.0)
      .option("--cloud-ground-albedo", "X",
              "with the slab lighting, the ground's albedo for the light it bounces into the clouds' bases, overriding "
              "the preset's (slab: 0.1; 0: no bounce)",
              &o.ground_albedo)
      .range(0.0, 1.0)
      .option("--cloud-ms-incidence", "X",
              "with the slab lighting, how far the multiple scattering takes the sun's incidence on a cloud's top where "
              "the sun's line leaves the cloud through it (a flat cloud under a low sun receives the sine of its "
              "elevation), overriding the preset's (slab: 0.5; 0: the light enters a face square to the sun)",
              &o.ms_incidence)
      .range(0.0, 1.0)
      .option("--cloud-ms-cavity", "X",
              "with the slab lighting, how far a cloud's surface seen from a chamber's air (enclosed air) keeps its edge "
              "lit, the chamber's walls sending back the light it loses, overriding the preset's (0: it darkens as an "
              "edge toward open air does)",
              &o.ms_cavity)
      .range(0.0, 1.0)
      .option("--cloud-sky-side", "X",
              "with the slab lighting, the clouds' sky light also through the nearest surface (a face sees (1 + n.y) / 2 of "
              "the sky's hemisphere) times X, overriding the preset's (slab: 2; 0: through the column straight up only)",
              &o.sky_side)
      .range(0.0, 4.0)
      .option("--cloud-ms-forward", "X",
              "with the slab lighting and the silver lining, the light the phase's forward lobe scatters past the first "
              "order, which goes on near the sun's direction and reaches deeper than the direct light (X x the lobe's "
              "excess over the isotropic at 0.7 of its eccentricity, through a quarter of the optical depth toward the sun), "
              "overriding the preset's (slab: 0.5; 0: none)",
              &o.ms_forward)
      .range(0.0, 4.0)
      .option("--envelope-ms-diffused", "X",
              "with the slab lighting, the envelope clouds' sun light past the first order of scattering is at least "
              "X times diffusion's through the cloud's optical depth toward the sun, 1 / (1 + 0.75 (1 - g) depth), where "
              "Wrenninge's octaves fall off faster (a thick bank), overriding the preset's (0: the octaves alone)",
              &o.envelope_ms_diffused)
      .range(0.0, 4.0)
      .option("--envelope-octave-eccentricity", "C",
              "with the slab lighting, how much of the phase's eccentricity each of the envelope clouds' octaves of "
              "scattering keeps from the one before (Wrenninge's c), overriding the preset's (slab: 0.5)",
              &o.envelope_eccentricity)
      .range(0.0, 1.0)
      .choice("--envelope-light-erosion", kOnOffNames, "preset",
              "with the slab lighting, the envelope clouds' light samples toward the sun erode by the detail noise's mean "
              "as the view ray's density is eroded by the detail (on), or see the density without it (off, the talk's), "
              "overriding the preset's (slab: on)",
              &o.envelope_light_erosion)
      .option("--cloud-light-sample-m", "M",
              "the length of the first marched light sample before the light grid, overriding the preset's (talk: 24 m, slab: 12 m)",
              &o.light_sample_m)
      .range(1.0, 200.0)
      .option("--cloud-light-samples", "N",
              "the number of marched light samples before the light grid, overriding the preset's (talk: 2)",
              &o.light_samples)
      .range(1.0, double(render::kMaxLightSamples))
      .option("--cloud-light-sample-growth", "R",
              "each marched light sample R times longer than the one before, overriding the preset's (talk: 1, slab: 3)",
              &o.light_sample_growth)
      .range(1.0, 4.0)
      .option("--cloud-step-growth", "X",
              "the in-cloud step may grow up to X times the talk's adaptive step: as 1 / sqrt(T) behind the view ray's "
              "transmittance T, and in thin cloud until a step spans an optical depth of 0.1 (default 4; 1: the talk's step)",
              &o.step_growth)
      .range(1.0, 16.0)
      .option("--cloud-split-distance", "M",
              "the 40/60 Hz split: the near segment, marched at half resolution, ends M metres from the camera "
              "(default: the talk's 200 on a GPU, 400 on a CPU device)",
              &o.split_distance_m)
      .range(1.0, 100000.0)
      .option("--cloud-edge-depth", "X",
              "with the slab lighting, the dark edges from the optical depth to the nearest surface, 1 - exp(-X depth), "
              "overriding the preset's (0: the talks' profile)",
              &o.edge_depth)
      .range(0.0, 100.0)
      .choice("--cloud-instance-shadows", kOnOffNames, "preset",
              "other cloud instances' clouds shadow an instance's (the storm cloud and the cloudscape), overriding the "
              "preset's (slab: on)",
              &o.instance_shadows)
      .option("--cloud-ms-lateral", "C",
              "with the slab lighting, the multiple scattering's leak through a surface nearer than both ends of the sun's "
              "line through the cloud, overriding the preset's (0: none)",
              &o.ms_lateral)
      .range(0.0, 100.0)
      .option("--cloud-ms-solve-iterations", "N",
              "with the solve lighting, rounds over the light grid's tiles of the multiple scattering's diffusion after a "
              "full rebuild of the grid (default 4)",
              &o.ms_solve_iterations)
      .range(0.0, 1000.0)
      .option("--cloud-ms-solve-local", "N",
              "with the solve lighting, red-black relaxations of a tile per visit (default 8)",
              &o.ms_solve_local)
      .range(1.0, 64.0)
      .option("--cloud-ms-solve-weight", "W",
              "with the solve lighting, the solved multiple scattering's weight against the slab's falloff, overriding "
              "the preset's (solve: 0.5; 1: the solved field alone)",
              &o.ms_solve_weight)
      .range(0.0, 1.0)
      .option("--cloud-ms-solve-strength", "X",
              "with the solve lighting, the solved field's strength, overriding the preset's (solve: 5; 1: the "
              "diffusion's fluence as it is)",
              &o.ms_solve_strength)
      .range(0.0, 100.0)
      .option("--cloud-ms-solve-omega", "W",
              "with the solve lighting, the relaxation factor of those sweeps (default 1.8; 1: Gauss-Seidel)",
              &o.ms_solve_omega)
      .range(0.5, 1.99)
      .choice("--cloud-sky-mean", kOnOffNames, "preset",
              "the clouds' sky light from the sky's mean radiance over the upper hemisphere (on) or 0.5 (zenith + "
              "horizon) (off), overriding the preset's (slab: off)",
              &o.sky_mean)
      .choice("--cloud-sky-hue", kOnOffNames, "preset",
              "with --cloud-sky-mean off, the clouds' sky light in the hue of the sky's mean over the upper hemisphere at "
              "the luminance of 0.5 (zenith + horizon) (on), or that colour itself (off), overriding the preset's (slab: on)",
              &o.sky_hue)
      .option("--cloud-ms-anisotropy", "X",
              "with the slab lighting, the multiple scattering's forward lobe near the lit surface as a fraction of the "
              "phase function's mean cosine, overriding the preset's (slab: 0.2; 0: isotropic)",
              &o.ms_anisotropy)
      .range(0.0, 2.0);
}

}  // namespace

void add_cloud_run_options(ArgParser& p, CloudRenderOptions& render, CloudSimulationOptions& simulation) {
  add_pass_options(p, render);
  add_lighting_options(p, render);
  p.option("--weather", "ID", "start in this weather state of the level's weather folder (clear, fair_cumulus, ...)",
           &simulation.weather)
      .option("--weather-dir", "DIR",
              "the folder of weather states (default: the level's, content/weather/ for the sample; the editor saves there)",
              &simulation.weather_dir);
}

}  // namespace cumulo::clouds
