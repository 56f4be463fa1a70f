#include "modules/clouds/scene/cloudscape.h"

#include <cmath>

#include "engine/core/error.h"

namespace cumulo::clouds {
namespace {

void check_keys(const JsonView& v, std::initializer_list<const char*> allowed) {
  for (const std::string& k : v.keys()) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || k == a;
    if (!ok) v[k].fail("unknown key \"" + k + "\"");
  }
}

}  // namespace

Cloudscape cloudscape_from_json(const JsonView& v) {
  if (!v.is_object()) v.fail("expected an object {\"asset\": PATH, ...}");
  check_keys(v, {"asset", "density", "wind", "dissipation", "rain"});
  Cloudscape c;
  if (v.has("asset")) {
    JsonView asset = v["asset"];
    c.asset = asset.as<std::string>();
    if (c.asset.empty()) asset.fail("expected a recipe (.json) or a folder of .nvdf files, got an empty path");
    c.where = asset.where();
  } else {
    c.where = v.where();  // no asset: only a cloud grown during play (CloudGrowth) may leave it out
  }
  if (v.has("density")) c.density = v["density"].as_float_in(0.0f, 1000.0f);
  if (v.has("dissipation")) c.dissipation = v["dissipation"].as_float_in(0.0f, 1.0f);
  if (v.has("rain")) c.rain = v["rain"].as_float_in(0.0f, 1.0f);
  if (v.has("wind")) {
    JsonView w = v["wind"];
    check_keys(w, {"direction", "speed"});
    if (w.has("direction")) {
      c.wind_direction = w["direction"].as_vec3();
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(c.wind_direction[i]) || std::fabs(c.wind_direction[i]) > 1e6f)
          w["direction"].fail("expected three finite numbers");
    }
    if (w.has("speed")) c.wind_speed = w["speed"].as_float_in(0.0f, 200.0f);
  }
  return c;
}

Json cloudscape_to_json(const Cloudscape& c) {
  Json j{{"density", c.density},
              {"wind", {{"direction", {c.wind_direction.x, c.wind_direction.y, c.wind_direction.z}}, {"speed", c.wind_speed}}},
              {"dissipation", c.dissipation},
              {"rain", c.rain}};
  if (!c.asset.empty()) j["asset"] = c.asset;
  return j;
}

void register_cloudscape_component(ecs::ComponentRegistry& registry) {
  registry.register_component<Cloudscape>("Cloudscape", cloudscape_to_json, cloudscape_from_json);
}

}  // namespace cumulo::clouds
