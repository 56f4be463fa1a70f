#include "editor/model/weather_params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "engine/core/error.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::editor {
namespace {

std::vector<std::string> split_path(std::string_view path) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    parts.emplace_back(path.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  for (const std::string& p : parts)
    if (p.empty()) fail("%.*s: not a dotted JSON path", int(path.size()), path.data());
  return parts;
}

std::string number_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A value for a message: a pasted novel in a number field is not echoed whole.
std::string shown(const Json& v) {
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

}  // namespace

const std::vector<ParamInfo>& weather_params() {
  static const std::vector<ParamInfo> params = [] {
    std::vector<ParamInfo> out;
    for (const std::string& group : weather_param_groups())
      for (const clouds::weather::WeatherField& f : clouds::weather::weather_fields())
        if (f.group == group)
          out.push_back({std::string(f.key), std::string(f.label), std::string(f.help), f.type(), f.min, f.max,
                         std::string(f.group),
                         f.rule == clouds::weather::FieldRule::Optional ? clouds::weather::field_json(f, {}) : Json()});
    return out;
  }();
  return params;
}

const std::vector<std::string>& weather_param_groups() {
  static const std::vector<std::string> groups = [] {
    std::vector<std::string> out;
    for (const clouds::weather::WeatherField& f : clouds::weather::weather_fields())
      if (!f.group.empty() && std::find(out.begin(), out.end(), f.group) == out.end()) out.emplace_back(f.group);
    return out;
  }();
  return groups;
}

const ParamInfo* find_param(std::string_view path) {
  for (const ParamInfo& p : weather_params())
    if (p.path == path) return &p;
  return nullptr;
}

Json get_param(const Json& state, std::string_view path) {
  const Json* at = &state;
  for (const std::string& key : split_path(path)) {
    if (!at->is_object() || !at->contains(key)) fail("%.*s: no such key in the state", int(path.size()), path.data());
    at = &(*at)[key];
  }
  return *at;
}

void set_param(Json& state, std::string_view path, const Json& value) {
  Json* at = &state;
  for (const std::string& key : split_path(path)) {
    if (at->is_null()) *at = Json::object();  // a member created on the way
    if (!at->is_object()) fail("%.*s: cannot set inside a non-object value", int(path.size()), path.data());
    at = &(*at)[key];  // creates the member (null) when missing
  }
  *at = value;
}

std::optional<std::string> check_param_value(const ParamInfo& p, const Json& value) {
  const std::string range = "[" + number_text(p.min) + ", " + number_text(p.max) + "]";
  auto out_of_range = [&](double v) -> std::optional<std::string> {
    if (std::isfinite(v) && v >= p.min && v <= p.max) return std::nullopt;
    return number_text(v) + " is out of range " + range;
  };
  switch (p.kind) {
    case ParamKind::Float:
      if (!value.is_number()) return "expected a number in " + range + ", got " + shown(value);
      return out_of_range(value.get<double>());
    case ParamKind::Int:
      if (value.is_number_float()) {
        const double d = value.get<double>();
        if (d != std::floor(d)) return "expected an integer in " + range + ", got " + shown(value);
        return out_of_range(d);
      }
      if (!value.is_number()) return "expected an integer in " + range + ", got " + shown(value);
      return value.is_number_unsigned() ? out_of_range(double(value.get<uint64_t>()))
                                        : out_of_range(double(value.get<int64_t>()));
    case ParamKind::Vec3: {
      if (!value.is_array() || value.size() != 3) return "expected an array of 3 numbers, got " + shown(value);
      for (const Json& c : value)
        if (!c.is_number() || !std::isfinite(c.get<double>()))
          return "expected an array of 3 numbers, got " + shown(value);
      return std::nullopt;  // the loader decides (it refuses a zero direction)
    }
    case ParamKind::Text:
      if (!value.is_string()) return "expected a string, got " + shown(value);
      return std::nullopt;
  }
  return std::nullopt;
}

Json normalize_param_value(const ParamInfo& p, const Json& value) {
  auto shortest = [](double d) -> Json {
    const float f = static_cast<float>(d);
    if (!std::isfinite(f)) return d;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, f);  // shortest text that reads back as f
    *r.ptr = '\0';
    return std::strtod(buf, nullptr);
  };
  if (p.kind == ParamKind::Float && value.is_number_float()) return shortest(value.get<double>());
  if (p.kind == ParamKind::Int && value.is_number_float()) {
    const double d = value.get<double>();
    if (d == std::floor(d) && d >= 0 && d <= 4294967295.0) return uint64_t(d);
  }
  if (p.kind == ParamKind::Vec3 && value.is_array()) {
    Json out = Json::array();
    for (const Json& c : value) out.push_back(c.is_number_float() ? shortest(c.get<double>()) : c);
    return out;
  }
  return value;
}

}  // namespace cumulo::editor
