#include "modules/clouds/frame/cloud_extraction.h"

#include <algorithm>

#include "engine/scene/components.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/weather/level_weather.h"

namespace cumulo::clouds {
namespace {

void apply_weather(const weather::WeatherState& w, SkyLayerFrame& sky) {
  sky.coverage = w.coverage;
  sky.cloud_type = w.cloud_type;
  sky.precipitation = std::max(w.precipitation, w.rain_intensity);
  sky.wind_direction = w.wind_direction;
  sky.wind_speed = w.wind_speed;
  sky.height_skew = w.height_skew;
  sky.anvil_bias = w.anvil_bias;
  sky.map = w.cloud_map;
  // Fewer high clouds under a closing low deck (they would not be seen) and in clear weather.
  sky.high_coverage =
      0.2f + 0.3f * std::clamp(w.coverage, 0.0f, 1.0f) * (1.0f - std::clamp(w.precipitation, 0.0f, 1.0f));
}

// Live lightning flashes, brightest first: the renderer's point lights (a bluish white); a ground
// discharge also shows its channel (a bolt down to sea level, hidden by the terrain where it stands
// higher) and lights the terrain from the channel's foot, an internal flash the ground faintly.
void extract_lightning(const ecs::World& world, CloudFrame& frame, cumulo::render::SceneLighting& lighting) {
  const glm::vec3 kLightningColor(0.75f, 0.8f, 1.0f);
  for (const gameplay::LightningLight& l : gameplay::lightning_lights(world, kMaxCloudPointLights)) {
    frame.lights.push_back({l.position, l.radius, kLightningColor * l.intensity});
    if (l.kind == gameplay::LightningKind::Ground) {
      BoltFrame bolt;
      bolt.intensity = l.intensity;
      for (const gameplay::BoltSegment& g : gameplay::lightning_bolt(l.position, 0.0f, l.seed))
        bolt.segments.push_back({g.a, g.b, g.brightness});
      if (!bolt.segments.empty()) {
        const glm::vec3 foot = bolt.segments[gameplay::kBoltMainSegments - 1].b;
        lighting.point_lights.push_back({foot + glm::vec3(0, 60, 0), 3000.0f, kLightningColor * (0.01f * l.intensity)});
      }
      frame.bolts.push_back(std::move(bolt));
    } else {
      lighting.point_lights.push_back({l.position, 2000.0f, kLightningColor * (0.0015f * l.intensity)});
    }
  }
}

}  // namespace

void apply_weather(const weather::WeatherState& w, CloudFrame& frame) {
  CloudWeatherLighting& l = frame.weather_lighting.emplace();
  l.extinction = w.lighting.absorption;
  l.hg_forward = w.lighting.phase_forward * (1.0f - w.lighting.silver_spread);
  l.hg_backward = w.lighting.phase_backward;
  l.hg_forward_weight = w.lighting.silver_intensity;
  l.ambient = w.lighting.ambient;
  for (CloudInstanceFrame& i : frame.instances) {
    i.density *= w.voxel_density;
    i.coverage = w.coverage;
    i.wind_direction = w.wind_direction;
    i.wind_speed = w.wind_speed;
  }
  for (EnvelopeFrame& e : frame.envelopes) {  // the component's own wind: mountains' clouds keep their authored flow
    e.coverage *= w.envelope_coverage;
    e.density *= w.envelope_density;
  }
  apply_weather(w, frame.sky);
}

float haze_mie_scale(float haze) { return std::max(0.25f, 1.0f + (std::clamp(haze, 0.0f, 1.0f) - 0.1f) * 10.0f); }

void extract_cloud_frame(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) {
  CloudFrame frame;
  world.view<const Cloudscape>().each([&](ecs::Entity e, const Cloudscape& c) {
    const auto* g = world.try_get<gameplay::CloudGrowth>(e);
    const bool grows = g && !g->resolved_spec.empty();
    if (c.resolved.empty() && !grows) return;  // added after the level loaded: not resolved (the editor will)
    CloudInstanceFrame i;
    i.folder = c.resolved;
    if (const auto* t = world.try_get<scene::Transform>(e)) {
      i.position = t->position;
      i.rotation = t->rotation;
      i.scale = t->scale.x;
    }
    i.density = c.density;
    i.wind_direction = c.wind_direction;
    i.wind_speed = c.wind_speed;
    i.dissipation = c.dissipation;
    i.rain = c.rain;
    if (grows) i.growth = CloudGrowthFrame{g->resolved_spec, e.bits(), g->target_steps, g->generation, g->voxel};
    frame.instances.push_back(std::move(i));
  });
  world.view<const envelope::OrographicClouds>().each([&](ecs::Entity, const envelope::OrographicClouds& c) {
    EnvelopeFrame e;
    e.spec = std::make_shared<const envelope::OrographicClouds>(c);
    e.bake_key = envelope::orographic_clouds_to_json(c).dump();
    e.density = c.density;
    e.edge_m = c.edge_m;
    e.wind_direction = c.wind_direction;
    e.wind_speed = c.wind_speed;
    frame.envelopes.push_back(std::move(e));
  });
  extract_lightning(world, frame, snapshot.lighting);
  frame.weather = weather::weather_drawn(world);
  if (frame.weather) {
    apply_weather(*frame.weather, frame);
    // The weather's haze thickens the air's aerosols: the atmosphere's Mie density and the height fog.
    const float mie = haze_mie_scale(frame.weather->haze);
    snapshot.lighting.mie_scale = mie;
    snapshot.lighting.fog_density *= mie;
  }
  snapshot.extensions.set(std::move(frame));
}

}  // namespace cumulo::clouds
