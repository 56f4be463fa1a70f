#include "modules/clouds/envelope/orographic_clouds.h"

#include <cmath>

#include "engine/core/error.h"

namespace cumulo::clouds::envelope {
namespace {

namespace fs = std::filesystem;

// Beyond these a value is a typo, and heights must stay clear of kEmptyTop / kEmptyBottom (envelope_maps.h).
constexpr float kMaxCoordinateM = 1.0e6f;
constexpr float kMaxHeightM = 2.0e4f;

void check_keys(const JsonView& v, std::initializer_list<const char*> allowed) {
  if (!v.is_object()) v.fail("expected an object");
  for (const std::string& k : v.keys()) {
    bool ok = false;
    std::string list;
    for (const char* a : allowed) {
      ok = ok || k == a;
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    if (!ok) v[k].fail("unknown key \"" + k + "\" (expected one of: " + list + ")");
  }
}

float positive(const JsonView& v, float hi) {
  const float x = v.as<float>();
  if (!(x > 0.0f) || x > hi) v.fail(strf("expected a number > 0 and <= %g, got %g", hi, x));
  return x;
}

float height(const JsonView& v) { return v.as_float_in(-kMaxHeightM, kMaxHeightM); }

glm::vec2 point2(const JsonView& v) {
  const glm::vec2 p = v.as_vec2();
  if (std::fabs(p.x) > kMaxCoordinateM || std::fabs(p.y) > kMaxCoordinateM)
    v.fail(strf("expected world x, z within +-%g m", kMaxCoordinateM));
  return p;
}

EnvelopeRegion region_from_json(const JsonView& v) {
  check_keys(v, {"center", "radius_m"});
  return EnvelopeRegion{point2(v["center"]), positive(v["radius_m"], kMaxCoordinateM)};
}

CapRule cap_from_json(const JsonView& v) {
  CapRule c;
  const JsonView center = v["center"];
  if (center.raw().is_string()) {
    if (center.as<std::string>() != "peak") center.fail("expected [x, z] or \"peak\"");
    c.at_peak = true;
  } else {
    c.center = point2(center);
  }
  c.radius_m = positive(v["radius_m"], kMaxCoordinateM);
  c.base_m = height(v["base_m"]);
  c.top_m = height(v["top_m"]);
  if (!(c.top_m - c.base_m >= kMinThicknessM))
    v["top_m"].fail(strf("top_m (%g) must be at least %g m above base_m (%g)", c.top_m, kMinThicknessM, c.base_m));
  return c;
}

BankRule bank_from_json(const JsonView& v) {
  BankRule b;
  const JsonView wind = v["wind_from"];
  b.wind_from = wind.as_vec3();
  if (!(glm::length(glm::vec2(b.wind_from.x, b.wind_from.z)) > 1e-6f) || glm::length(b.wind_from) > kMaxCoordinateM)
    wind.fail("expected a direction with a horizontal (x, z) part");
  const JsonView range = v["terrain_m"];
  b.terrain_m = range.as_vec2();
  if (!(b.terrain_m.y > b.terrain_m.x) || std::fabs(b.terrain_m.x) > kMaxHeightM ||
      std::fabs(b.terrain_m.y) > kMaxHeightM)
    range.fail(strf("expected [low, high] with low < high within +-%g m", kMaxHeightM));
  if (v.has("base_above_terrain_m")) b.base_above_terrain_m = height(v["base_above_terrain_m"]);
  const JsonView thickness = v["thickness_m"];
  b.thickness_m = thickness.as_float_in(kMinThicknessM, kMaxHeightM);
  return b;
}

LayerRule layer_from_json(const JsonView& v) {
  LayerRule l;
  l.top_m = height(v["top_m"]);
  if (v.has("base_above_terrain_m")) l.base_above_terrain_m = height(v["base_above_terrain_m"]);
  // The lowest bottom the layer can have is sea level + base: any closer to the top it is empty everywhere.
  if (!(l.top_m - l.base_above_terrain_m >= kMinThicknessM))
    v["top_m"].fail(strf("top_m (%g) must be at least %g m above base_above_terrain_m (%g) (empty even at sea level)",
                         l.top_m, kMinThicknessM, l.base_above_terrain_m));
  l.below_terrain_m = v.has("below_terrain_m") ? height(v["below_terrain_m"]) : l.top_m;
  return l;
}

EnvelopeRule rule_from_json(const JsonView& v) {
  if (!v.is_object()) v.fail("expected a rule object {\"type\": \"cap\" | \"bank\" | \"layer\", ...}");
  EnvelopeRule r;
  r.where = v.where();
  const RuleType type = v["type"].as_name(kRuleTypeNames);
  switch (type) {
    case RuleType::Cap:
      check_keys(v, {"type", "center", "radius_m", "base_m", "top_m", "coverage", "detail_type", "variation", "variation_m"});
      r.kind = cap_from_json(v);
      break;
    case RuleType::Bank:
      check_keys(v, {"type", "wind_from", "terrain_m", "base_above_terrain_m", "thickness_m", "coverage", "detail_type",
                     "variation", "variation_m", "region"});
      r.kind = bank_from_json(v);
      break;
    case RuleType::Layer:
      check_keys(v, {"type", "top_m", "base_above_terrain_m", "below_terrain_m", "coverage", "detail_type", "variation",
                     "variation_m", "region"});
      r.kind = layer_from_json(v);
      break;
  }
  if (v.has("coverage")) r.coverage = v["coverage"].as_float_in(0.0f, 1.0f);
  if (v.has("detail_type")) r.detail_type = v["detail_type"].as_float_in(0.0f, 1.0f);
  if (v.has("variation")) r.variation = v["variation"].as_float_in(0.0f, 1.0f);
  if (v.has("variation_m")) r.variation_m = v["variation_m"].as_float_in(1.0f, 100000.0f);
  if (v.has("region")) r.region = region_from_json(v["region"]);
  return r;
}

PaintedMapFile map_file(const JsonView& v) {
  PaintedMapFile f{v.as<std::string>(), v.where()};
  if (f.path.empty()) v.fail("expected a PNG path (relative to the level file), got an empty string");
  return f;
}

PaintedMapSet maps_from_json(const JsonView& v) {
  check_keys(v, {"bottom", "top", "coverage", "detail", "height_range", "relative_to"});
  PaintedMapSet m;
  m.bottom = map_file(v["bottom"]);
  m.top = map_file(v["top"]);
  if (v.has("coverage")) m.coverage = map_file(v["coverage"]);
  if (v.has("detail")) m.detail = map_file(v["detail"]);
  const JsonView range = v["height_range"];
  m.height_range = range.as_vec2();
  if (!(m.height_range.y > m.height_range.x) || std::fabs(m.height_range.x) > kMaxHeightM ||
      std::fabs(m.height_range.y) > kMaxHeightM)
    range.fail(strf("expected [low, high] with low < high within +-%g m", kMaxHeightM));
  if (v.has("relative_to")) m.relative_to_terrain = v["relative_to"].as_enum({"sea", "terrain"}) == 1;
  return m;
}

Json vec2_json(glm::vec2 p) { return Json::array({p.x, p.y}); }

Json rule_to_json(const EnvelopeRule& r) {
  Json j{{"type", name_of(kRuleTypeNames, r.type())}, {"coverage", r.coverage}, {"detail_type", r.detail_type},
         {"variation", r.variation}, {"variation_m", r.variation_m}};
  if (const auto* c = std::get_if<CapRule>(&r.kind)) {
    j["center"] = c->at_peak ? Json("peak") : vec2_json(c->center);
    j["radius_m"] = c->radius_m;
    j["base_m"] = c->base_m;
    j["top_m"] = c->top_m;
  } else if (const auto* b = std::get_if<BankRule>(&r.kind)) {
    j["wind_from"] = {b->wind_from.x, b->wind_from.y, b->wind_from.z};
    j["terrain_m"] = vec2_json(b->terrain_m);
    j["base_above_terrain_m"] = b->base_above_terrain_m;
    j["thickness_m"] = b->thickness_m;
  } else if (const auto* l = std::get_if<LayerRule>(&r.kind)) {
    j["top_m"] = l->top_m;
    j["base_above_terrain_m"] = l->base_above_terrain_m;
    j["below_terrain_m"] = l->below_terrain_m;
  }
  if (r.region) j["region"] = {{"center", vec2_json(r.region->center)}, {"radius_m", r.region->radius_m}};
  return j;
}

GreyImage read_map(const PaintedMapFile& f, const fs::path& level_dir) {
  if (f.path.empty()) return {};
  const fs::path p(f.path);
  const fs::path file = (p.is_absolute() ? p : level_dir / p).lexically_normal();
  try {
    return read_grey_png(file);
  } catch (const Error& e) {
    fail("%s: %s", f.where.c_str(), e.what());
  }
}

}  // namespace

OrographicClouds orographic_clouds_from_json(const JsonView& v) {
  check_keys(v, {"extent", "resolution", "density", "coverage", "edge_m", "wind", "rules", "maps"});
  OrographicClouds c;
  c.where = v.where();
  const JsonView extent = v["extent"];
  check_keys(extent, {"min", "max"});
  c.extent_min = point2(extent["min"]);
  c.extent_max = point2(extent["max"]);
  if (!(c.extent_max.x > c.extent_min.x) || !(c.extent_max.y > c.extent_min.y))
    extent.fail(strf("expected max > min in x and z, got min [%g, %g], max [%g, %g]", c.extent_min.x, c.extent_min.y,
                     c.extent_max.x, c.extent_max.y));
  if (v.has("resolution")) {
    const JsonView r = v["resolution"];
    c.resolution = r.as<uint32_t>();
    if (c.resolution < 16 || c.resolution > 1024)
      r.fail(strf("expected 16..1024 texels per side, got %u", c.resolution));
  }
  if (v.has("density")) c.density = v["density"].as_float_in(0.0f, 1000.0f);
  if (v.has("coverage")) c.coverage = v["coverage"].as_float_in(0.0f, 1.0f);
  if (v.has("edge_m")) c.edge_m = v["edge_m"].as_float_in(0.1f, 1.0e4f);
  if (v.has("wind")) {
    const JsonView w = v["wind"];
    check_keys(w, {"direction", "speed"});
    if (w.has("direction")) {
      c.wind_direction = w["direction"].as_vec3();
      if (glm::length(c.wind_direction) > kMaxCoordinateM) w["direction"].fail("expected three numbers within +-1e6");
    }
    if (w.has("speed")) c.wind_speed = w["speed"].as_float_in(0.0f, 200.0f);
  }
  if (v.has("rules"))
    for (const JsonView& r : v["rules"].elements()) c.rules.push_back(rule_from_json(r));
  if (v.has("maps")) c.maps = maps_from_json(v["maps"]);
  return c;
}

Json orographic_clouds_to_json(const OrographicClouds& c) {
  Json rules = Json::array();
  for (const EnvelopeRule& r : c.rules) rules.push_back(rule_to_json(r));
  Json j{
      {"extent", {{"min", vec2_json(c.extent_min)}, {"max", vec2_json(c.extent_max)}}},
      {"resolution", c.resolution},
      {"density", c.density},
      {"coverage", c.coverage},
      {"edge_m", c.edge_m},
      {"wind", {{"direction", {c.wind_direction.x, c.wind_direction.y, c.wind_direction.z}}, {"speed", c.wind_speed}}},
      {"rules", rules}};
  if (c.maps) {
    const PaintedMapSet& m = *c.maps;
    Json maps{{"bottom", m.bottom.path},
              {"top", m.top.path},
              {"height_range", vec2_json(m.height_range)},
              {"relative_to", m.relative_to_terrain ? "terrain" : "sea"}};
    if (!m.coverage.path.empty()) maps["coverage"] = m.coverage.path;
    if (!m.detail.path.empty()) maps["detail"] = m.detail.path;
    j["maps"] = maps;
  }
  return j;
}

void register_orographic_clouds_component(ecs::ComponentRegistry& registry) {
  registry.register_component<OrographicClouds>("OrographicClouds", orographic_clouds_to_json,
                                                orographic_clouds_from_json);
}

PaintedMaps load_painted_maps(const PaintedMapSet& maps, const fs::path& level_dir) {
  PaintedMaps p;
  p.bottom = read_map(maps.bottom, level_dir);
  p.top = read_map(maps.top, level_dir);
  p.coverage = read_map(maps.coverage, level_dir);
  p.detail = read_map(maps.detail, level_dir);
  auto same_size = [&](const GreyImage& img, const PaintedMapFile& f) {
    if (!img.empty() && (img.width != p.bottom.width || img.height != p.bottom.height))
      fail("%s: %s is %ux%u, but bottom (%s) is %ux%u: the painted maps must all have the same size", f.where.c_str(),
           f.path.c_str(), img.width, img.height, maps.bottom.path.c_str(), p.bottom.width, p.bottom.height);
  };
  same_size(p.top, maps.top);
  same_size(p.coverage, maps.coverage);
  same_size(p.detail, maps.detail);
  return p;
}

void resolve_orographic_clouds(OrographicClouds& c, const fs::path& level_dir) {
  c.level_dir = level_dir;
  c.painted = c.maps ? std::make_shared<const PaintedMaps>(load_painted_maps(*c.maps, level_dir)) : nullptr;
}

}  // namespace cumulo::clouds::envelope
