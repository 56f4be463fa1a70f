#include "engine/scene/serialization.h"

#include <cmath>

#include "engine/core/message.h"
#include "engine/scene/components.h"

namespace cumulo::scene {

void check_keys(const JsonView& v, std::initializer_list<const char*> allowed) {
  if (!v.is_object()) v.fail("expected an object");
  for (const std::string& key : v.keys()) {
    bool ok = false;
    std::string list;
    for (const char* a : allowed) {
      ok = ok || key == a;
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    if (!ok) v[key].fail("unknown key " + quote(key, 64) + " (expected one of: " + list + ")");
  }
}

namespace {

Json vec(const glm::vec3& v) { return Json::array({v.x, v.y, v.z}); }

float positive(const JsonView& v) {
  float f = v.as<float>();
  if (!(f > 0.0f)) v.fail(strf("expected a positive number, got %g", double(f)));
  return f;
}

glm::vec3 color(const JsonView& v) {
  glm::vec3 c = v.as_vec3();
  for (int i = 0; i < 3; ++i)
    if (c[i] < 0.0f) v.at(size_t(i)).fail("colour components must not be negative");
  return c;
}

Transform transform_from_json(const JsonView& v) {
  check_keys(v, {"position", "rotation", "euler_deg", "look_at", "scale"});
  Transform t;
  t.position = v.get_vec3("position", t.position);
  int rotations = int(v.has("rotation")) + int(v.has("euler_deg")) + int(v.has("look_at"));
  if (rotations > 1) v.fail("give at most one of \"rotation\", \"euler_deg\" and \"look_at\"");
  if (v.has("rotation")) {
    JsonView r = v["rotation"];
    glm::vec4 q = r.as_vec4();
    float len = glm::length(q);
    if (std::abs(len - 1.0f) > 1e-3f) r.fail(strf("expected a unit quaternion [x, y, z, w], its length is %g", double(len)));
    t.rotation = glm::normalize(glm::quat(q.w, q.x, q.y, q.z));
  } else if (v.has("euler_deg")) {
    t.rotation = euler_degrees_to_quat(v["euler_deg"].as_vec3());
  } else if (v.has("look_at")) {
    JsonView la = v["look_at"];
    glm::vec3 target = la.as_vec3();
    if (glm::length(target - t.position) < 1e-3f) la.fail("look_at target coincides with the position");
    t.rotation = Transform::look_at(t.position, target).rotation;
  }
  if (v.has("scale")) {
    JsonView s = v["scale"];
    t.scale = s.raw().is_number() ? glm::vec3(s.as<float>()) : s.as_vec3();
    for (int i = 0; i < 3; ++i)
      if (t.scale[i] == 0.0f) s.fail("scale must not be zero");
  }
  return t;
}

Json transform_to_json(const Transform& t) {
  Json j = {{"position", vec(t.position)},
            {"rotation", Json::array({t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w})}};
  if (t.scale != glm::vec3(1.0f)) j["scale"] = vec(t.scale);
  return j;
}

Camera camera_from_json(const JsonView& v) {
  check_keys(v, {"fov_y_deg", "near", "far"});
  Camera c;
  if (v.has("fov_y_deg")) c.fov_y_deg = v["fov_y_deg"].as_float_in(1.0f, 179.0f);
  if (v.has("near")) c.near = positive(v["near"]);
  if (v.has("far")) c.far = positive(v["far"]);
  if (!(c.far > c.near)) (v.has("far") ? v["far"] : v).fail(strf("far (%g) must be greater than near (%g)", double(c.far), double(c.near)));
  return c;
}

ModelRef model_from_json(const JsonView& v) {
  check_keys(v, {"path", "cast_shadows"});
  ModelRef m;
  JsonView p = v["path"];
  m.path = p.as<std::string>();
  if (m.path.empty()) p.fail("empty model path");
  m.cast_shadows = v.get<bool>("cast_shadows", true);
  return m;
}

TimeOfDay time_from_json(const JsonView& v) {
  check_keys(v, {"hours", "day_of_year", "latitude_deg", "north_deg", "hours_per_second"});
  TimeOfDay t;
  if (v.has("hours")) {
    t.hours = v["hours"].as_float_in(0.0f, 24.0f);
    if (t.hours >= 24.0f) t.hours = 0.0f;
  }
  if (v.has("day_of_year")) {
    JsonView d = v["day_of_year"];
    t.day_of_year = d.as<int>();
    if (t.day_of_year < 1 || t.day_of_year > 366) d.fail(strf("expected a day of the year in 1..366, got %d", t.day_of_year));
  }
  if (v.has("latitude_deg")) t.latitude_deg = v["latitude_deg"].as_float_in(-90.0f, 90.0f);
  if (v.has("north_deg")) t.north_deg = v["north_deg"].as_float_in(-360.0f, 360.0f);
  if (v.has("hours_per_second")) t.hours_per_second = v["hours_per_second"].as_float_in(-24.0f, 24.0f);
  return t;
}

Json time_to_json(const TimeOfDay& t) {
  return {{"hours", t.hours}, {"day_of_year", t.day_of_year}, {"latitude_deg", t.latitude_deg},
          {"north_deg", t.north_deg}, {"hours_per_second", t.hours_per_second}};
}

Sun sun_from_json(const JsonView& v) {
  check_keys(v, {"color", "illuminance"});
  Sun s;
  if (v.has("color")) s.color = color(v["color"]);
  if (v.has("illuminance")) s.illuminance = v["illuminance"].as_float_in(0.0f, 1e6f);
  return s;
}

Ocean ocean_from_json(const JsonView& v) {
  check_keys(v, {"sea_level", "color"});
  Ocean o;
  if (v.has("sea_level")) o.sea_level = v["sea_level"].as_float_in(-1e4f, 1e4f);
  if (v.has("color")) o.color = color(v["color"]);
  return o;
}

}  // namespace

void register_components(ecs::ComponentRegistry& reg) {
  reg.register_component<Transform>("Transform", transform_to_json, transform_from_json);
  reg.register_component<Camera>(
      "Camera", [](const Camera& c) { return Json{{"fov_y_deg", c.fov_y_deg}, {"near", c.near}, {"far", c.far}}; },
      camera_from_json);
  reg.register_component<ModelRef>(
      "ModelRef",
      [](const ModelRef& m) {
        Json j = {{"path", m.path}};
        if (!m.cast_shadows) j["cast_shadows"] = false;
        return j;
      },
      model_from_json);
  reg.register_component<TimeOfDay>("TimeOfDay", time_to_json, time_from_json);
  reg.register_component<Sun>(
      "Sun", [](const Sun& s) { return Json{{"color", vec(s.color)}, {"illuminance", s.illuminance}}; }, sun_from_json);
  reg.register_component<Ocean>(
      "Ocean", [](const Ocean& o) { return Json{{"sea_level", o.sea_level}, {"color", vec(o.color)}}; },
      ocean_from_json);
}

}  // namespace cumulo::scene
