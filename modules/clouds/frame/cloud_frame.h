#pragma once
// The clouds' frame: everything the world says about the clouds this frame, extracted once
// (extract_cloud_frame, cloud_extraction.h) into the snapshot's extensions. The renderer (render/) reads
// only this; the simulation (weather/, gameplay/) never sees it. Plain data: no GPU types.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/envelope/orographic_clouds.h"
#include "modules/clouds/scene/density_query.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds {

// A cloud grown during play (gameplay::CloudGrowth on the entity): the renderer steps its simulation toward
// `target_steps` (at most a few steps a frame) and draws it in place of the folder's asset.
struct CloudGrowthFrame {
  std::filesystem::path spec;  // the grow spec, resolved
  uint64_t key = 0;            // the entity: one simulation per growing cloud
  int target_steps = 0;
  uint32_t generation = 0;     // a new one: the simulation starts again from its first step
  float voxel = 8.0f;          // the march's voxel, game metres (CloudGrowth "voxel")
};

// One Cloudscape entity, its weather applied (density x voxel_density, coverage, wind).
struct CloudInstanceFrame : CloudPlacement {
  std::filesystem::path folder;  // resolved NVDF folder (empty for a grown cloud without a Cloudscape asset)
  float rain = 0.0f;             // Cloudscape "rain" (0..1), before dissipation
  std::optional<CloudGrowthFrame> growth;
};

// At most this many point lights a frame: the march's CLOUD_MAX_POINT_LIGHTS (cloud_renderer.h checks).
inline constexpr uint32_t kMaxCloudPointLights = 4;

struct CloudPointLight {  // secondary sources (lightning): the talk's potential-energy field
  glm::vec3 position{0.0f};
  float radius = 100.0f;
  glm::vec3 color{0.0f};  // colour x intensity (linear)
};

struct BoltSegmentFrame {
  glm::vec3 a{0.0f}, b{0.0f};
  float brightness = 1.0f;
};
struct BoltFrame {
  std::vector<BoltSegmentFrame> segments;  // gameplay::lightning_bolt
  float intensity = 0.0f;                  // the flash's envelope x peak intensity now
};

// What a weather state sets in the voxel clouds' lighting (weather_to_frame, cloud_extraction.h):
//   lighting.absorption       -> CloudSettings::extinction (1/m per unit density)
//   lighting.phase.forward    -> hg_forward x (1 - lighting.silver.spread)   (spread widens the forward lobe)
//   lighting.phase.backward   -> hg_backward
//   lighting.silver.intensity -> hg_forward_weight (the silver lining's share of the dual-lobe phase)
//   lighting.ambient          -> the sky ambient's multiplier
struct CloudWeatherLighting {
  float extinction = 0.0f, hg_forward = 0.0f, hg_backward = 0.0f, hg_forward_weight = 0.0f;
  float ambient = 1.0f;
};

// The 2.5D sky's parameters (render/sky_layer.h) with defaults; the weather state drives the first group.
struct SkyLayerFrame {
  // From the weather state.
  float coverage = 0.4f;       // 0..1: scales the map's R (0.5 in the map = this coverage)
  float cloud_type = 1.0f;     // 0 stratus .. 0.5 stratocumulus .. 1 cumulus (the map's B shifts it)
  float precipitation = 0.0f;  // 0..1: scales the map's G; grows cumulonimbus at 70 % coverage
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 4.0f;     // m/s: the map drifts, the noise scrolls
  float height_skew = 0.1f;    // tops lean downwind by this fraction of the shell's thickness
  float anvil_bias = 0.0f;
  weather::CloudMapSource map;
  // The layer itself (2015: "between 1500 and 4000 meters", "within a 35,000 meter radius", cumulus
  // toward the horizon from 15 km at about 50 % coverage).
  float bottom_m = 1500.0f, top_m = 4000.0f;
  float planet_radius_m = 6360e3f;
  float draw_distance_m = 35000.0f;
  // A camera inside the shell (or within this distance of it) sees the layer from this distance on, fading in over
  // as much again: the layer is the distant sky (the 2015 talk's player stands under it), and marched from inside, its
  // 64-128 steps over the ray's kilometres turned the deck around the camera into an even veil over the whole view (the
  // sample's `overview` camera, 1900 m up outside the voxel box). 0: none.
  float near_fade_m = 1500.0f;
  float horizon_bias_start_m = 15000.0f, horizon_coverage = 0.5f;
  float high_coverage = 0.35f;  // the 2D cirrus / alto layers
  float high_altitude_m = 7000.0f;
  float yield_fade_m = 1500.0f;  // the density fades in over this distance outside a voxel box's footprint
  float yield_fade_vertical_m = 400.0f;  // and over this height above (or below) the box
  float extinction_scale = 0.4f; // x the voxel clouds' extinction: the shell's densities are per 10 m, not per 1 m of voxel
};

// The Envelope method's orographic clouds of an OrographicClouds component (render/envelope_layer.h): its spec, which the
// renderer bakes into maps over the terrain (again when bake_key changes), and what may change every frame.
struct EnvelopeFrame {
  std::shared_ptr<const envelope::OrographicClouds> spec;
  std::string bake_key;  // the spec's JSON (orographic_clouds_to_json)
  float density = 1.0f;  // the component's
  float coverage = 1.0f; // 0..1 x the baked coverage
  float edge_m = 35.0f;
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;
};

// The snapshot extension of the clouds module.
struct CloudFrame {
  std::vector<CloudInstanceFrame> instances;
  std::vector<CloudPointLight> lights;
  std::vector<BoltFrame> bolts;  // ground discharges live this frame (their visible channels)
  // The weather drawn this frame: the editor's preview, else the first WeatherScheduler's blend, else the
  // state --weather names (none: the Cloudscapes' own values and the talk's lighting constants).
  std::optional<weather::WeatherState> weather;
  std::optional<CloudWeatherLighting> weather_lighting;  // from `weather`
  SkyLayerFrame sky;  // the 2.5D sky's parameters (drawn with --cloud-sky; driven by `weather`)
  std::vector<EnvelopeFrame> envelopes;  // the level's OrographicClouds (the renderer draws the first)
};

}  // namespace cumulo::clouds
