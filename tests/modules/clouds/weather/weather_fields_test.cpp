// The weather's field table (issue 22): the shipped schema describes the same keys with the same types,
// ranges and required keys; the loader and blend() follow every row.
#include "modules/clouds/weather/weather_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <string>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "modules/clouds/weather/weather_library.h"

using namespace cumulo;
using namespace cumulo::clouds::weather;

namespace {

struct SchemaKeys {
  std::map<std::string, Json> leaves;   // dotted key -> its schema
  std::map<std::string, Json> objects;  // dotted path ("" the root) -> its schema
};

SchemaKeys schema_keys(const Json& schema) {
  SchemaKeys out;
  std::function<void(const Json&, const std::string&)> walk = [&](const Json& node, const std::string& path) {
    out.objects[path] = node;
    const Json properties = node.value("properties", Json::object());
    for (const auto& [k, v] : properties.items()) {
      const std::string key = path.empty() ? k : path + "." + k;
      if (v.value("type", "") == "object")
        walk(v, key);
      else
        out.leaves[key] = v;
    }
  };
  walk(schema, "");
  return out;
}

const char* schema_type(FieldType t) {
  switch (t) {
    case FieldType::Float:
      return "number";
    case FieldType::Int:
      return "integer";
    case FieldType::Vec3:
      return "array";
    case FieldType::Text:
      return "string";
  }
  return "?";
}

TEST(WeatherFields, SchemaAgreesWithTheTableKeyByKey) {
  const JsonDocument doc = load_json_file(repo_root() / "content/schemas/weather.schema.json");
  const SchemaKeys schema = schema_keys(doc.json());
  for (const auto& [key, s] : schema.leaves)
    EXPECT_NE(find_weather_field(key), nullptr) << key << ": in the schema, not in weather_fields.cpp";
  for (const WeatherField& f : weather_fields()) {
    const std::string key(f.key);
    auto it = schema.leaves.find(key);
    if (it == schema.leaves.end()) {
      ADD_FAILURE() << key << ": in weather_fields.cpp, not in the schema";
      continue;
    }
    const Json& s = it->second;
    EXPECT_EQ(s.value("type", ""), schema_type(f.type())) << key << ": type";
    if (f.type() == FieldType::Float || f.type() == FieldType::Int) {
      EXPECT_EQ(s.value("minimum", Json()), Json(f.min)) << key << ": minimum";
      EXPECT_EQ(s.value("maximum", Json()), Json(f.max)) << key << ": maximum";
    }
    if (f.type() == FieldType::Vec3) {
      EXPECT_EQ(s.value("minItems", 0), 3) << key << ": minItems";
      EXPECT_EQ(s.value("maxItems", 0), 3) << key << ": maxItems";
      EXPECT_EQ(s.value("items", Json::object()).value("type", ""), "number") << key << ": items";
    }
    if (s.contains("default")) {
      if (f.by_hand())
        ADD_FAILURE() << key << ": the schema gives a default, the table has no member to hold it";
      else
        EXPECT_EQ(s["default"], field_json(f, WeatherState{})) << key << ": default";
    }
  }
  // The same objects, each closed, with the same required keys.
  for (const auto& [path, s] : schema.objects) {
    const WeatherObject* o = find_weather_object(path);
    if (!o) {
      ADD_FAILURE() << "object \"" << path << "\": in the schema, not in weather_fields.cpp";
      continue;
    }
    EXPECT_EQ(s.value("additionalProperties", true), false) << "object \"" << path << "\"";
    std::set<std::string> keys, required;
    for (const auto& [k, v] : s.at("properties").items()) keys.insert(k);
    for (const Json& r : s.value("required", Json::array())) required.insert(r.get<std::string>());
    EXPECT_EQ(keys, std::set<std::string>(o->keys.begin(), o->keys.end())) << "object \"" << path << "\": keys";
    EXPECT_EQ(required, o->required) << "object \"" << path << "\": required keys";
  }
}

TEST(WeatherFields, TableIsConsistent) {
  std::set<std::string_view> keys;
  for (const WeatherField& f : weather_fields()) {
    EXPECT_TRUE(keys.insert(f.key).second) << f.key << ": twice";
    // A key is either a value or an object holding values, never both.
    EXPECT_EQ(find_weather_object(f.key), nullptr) << f.key;
    if (f.blend == FieldBlend::Lerp) {
      EXPECT_TRUE(f.type() == FieldType::Float || f.type() == FieldType::Vec3) << f.key << ": cannot be lerped";
    }
    if (f.blend == FieldBlend::Velocity) {
      EXPECT_TRUE(f.key == "wind.direction" || f.key == "wind.speed") << f.key;
    }
    if (f.rule == FieldRule::Direction) {
      EXPECT_EQ(f.type(), FieldType::Vec3) << f.key;
    }
    if (f.by_hand()) {
      EXPECT_TRUE(f.group.empty()) << f.key << ": a hand-written key has no member for the editor to show";
      EXPECT_EQ(f.blend, FieldBlend::Nearest) << f.key;
    } else {
      EXPECT_FALSE(f.group.empty() || f.label.empty() || f.help.empty())
          << f.key << ": the editor's group, label, help";
    }
    if (f.type() == FieldType::Float || f.type() == FieldType::Int) {
      EXPECT_LT(f.min, f.max) << f.key;
    }
  }
  ASSERT_NE(find_weather_object(""), nullptr);
  EXPECT_EQ(find_weather_object("")->keys.front(), "$schema");  // first in a saved file
  EXPECT_EQ(find_weather_object("coverage"), nullptr);
  EXPECT_EQ(find_weather_field("lighting"), nullptr);
}

// Every numeric row is range checked, and the message names the file and the row's JSON path.
TEST(WeatherFields, TheLoaderChecksEveryRowNamingItsKey) {
  const JsonDocument shipped = load_json_file(WeatherLibrary::default_folder() / "fair_cumulus.json");
  for (const WeatherField& f : weather_fields()) {
    if (f.type() != FieldType::Float && f.type() != FieldType::Int) continue;
    std::string pointer = "/" + std::string(f.key);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    Json j = shipped.json();
    j[Json::json_pointer(pointer)] = f.max + 1.0;
    const JsonDocument broken(j, "broken.json");
    try {
      weather_state_from_json(broken.view(), "broken", "broken.json");
      ADD_FAILURE() << f.key << ": no error for " << f.max + 1.0;
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("broken.json"), std::string::npos) << f.key << ": " << m;
      EXPECT_NE(m.find("$." + std::string(f.key) + ":"), std::string::npos) << f.key << ": " << m;
    }
  }
}

TEST(WeatherFields, BlendFollowsEveryRow) {
  const WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
  const WeatherState& a = lib.get("fair_cumulus");
  const WeatherState& b = lib.get("storm");
  const WeatherState quarter = blend(a, b, 0.25f).state;
  for (const WeatherField& f : weather_fields()) {
    if (f.by_hand()) continue;
    const Json x = field_json(f, a), y = field_json(f, b), got = field_json(f, quarter);
    if (f.blend == FieldBlend::Nearest) {
      EXPECT_EQ(got, x) << f.key;
    }
    if (f.blend == FieldBlend::Lerp && f.type() == FieldType::Float) {
      EXPECT_FLOAT_EQ(got.get<float>(), x.get<float>() + (y.get<float>() - x.get<float>()) * 0.25f) << f.key;
    }
  }
}

}  // namespace
