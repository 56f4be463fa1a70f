#include "engine/core/json.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "engine/core/file_io.h"

namespace cumulo {

JsonDocument parse_json_text(const std::string& text, const std::string& name) {
  try {
    return JsonDocument(Json::parse(text), name);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    size_t byte = e.byte > 0 ? e.byte - 1 : 0;
    size_t line = 1, col = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string what = e.what();
    // nlohmann prefixes "[json.exception.parse_error.101] parse error at line L, column C: ".
    auto colon = what.find(": ", what.find("parse error"));
    std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
    throw Error(strf("%s:%zu:%zu: JSON syntax error: %s", name.c_str(), line, col, detail.c_str()));
  }
}

JsonDocument load_json_file(const std::filesystem::path& path) {
  return parse_json_text(read_file_text(path), path.string());
}

std::string JsonView::where() const { return *file_ + ": " + path_; }

void JsonView::fail(const std::string& message) const { throw Error(where() + ": " + message); }

std::string JsonView::type_name() const {
  return value_->is_number_integer() ? "integer" : value_->type_name();
}

size_t JsonView::size() const {
  if (!value_->is_array() && !value_->is_object()) fail("expected an array or object, got " + type_name());
  return value_->size();
}

JsonView JsonView::operator[](const std::string& key) const {
  if (!value_->is_object()) fail("expected an object, got " + type_name());
  auto it = value_->find(key);
  if (it == value_->end()) fail("missing required member \"" + key + "\"");
  return JsonView(&*it, file_, path_ + "." + key);
}

JsonView JsonView::at(size_t index) const {
  if (!value_->is_array()) fail("expected an array, got " + type_name());
  if (index >= value_->size()) fail(strf("index %zu out of range (size %zu)", index, value_->size()));
  return JsonView(&(*value_)[index], file_, strf("%s[%zu]", path_.c_str(), index));
}

std::vector<JsonView> JsonView::elements() const {
  if (!value_->is_array()) fail("expected an array, got " + type_name());
  std::vector<JsonView> out;
  for (size_t i = 0; i < value_->size(); ++i) out.push_back(at(i));
  return out;
}

std::vector<std::string> JsonView::keys() const {
  if (!value_->is_object()) fail("expected an object, got " + type_name());
  std::vector<std::string> out;
  for (auto it = value_->begin(); it != value_->end(); ++it) out.push_back(it.key());
  return out;
}

template <>
bool JsonView::as<bool>() const {
  if (!value_->is_boolean()) fail("expected a boolean, got " + type_name());
  return value_->get<bool>();
}
template <>
double JsonView::as<double>() const {
  if (!value_->is_number()) fail("expected a number, got " + type_name());
  double v = value_->get<double>();
  if (!std::isfinite(v)) fail("expected a finite number");
  return v;
}
template <>
float JsonView::as<float>() const {
  return static_cast<float>(as<double>());
}
template <>
int64_t JsonView::as<int64_t>() const {
  if (value_->is_number_integer()) return value_->get<int64_t>();
  if (value_->is_number_float()) {
    double v = value_->get<double>();
    if (v == std::floor(v) && std::abs(v) < 9e15) return static_cast<int64_t>(v);
  }
  fail("expected an integer, got " + type_name());
}
template <>
int JsonView::as<int>() const {
  int64_t v = as<int64_t>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) fail("integer out of range");
  return static_cast<int>(v);
}
template <>
uint32_t JsonView::as<uint32_t>() const {
  int64_t v = as<int64_t>();
  if (v < 0 || v > std::numeric_limits<uint32_t>::max()) fail(strf("expected a non-negative 32-bit integer, got %lld", (long long)v));
  return static_cast<uint32_t>(v);
}
template <>
uint64_t JsonView::as<uint64_t>() const {
  int64_t v = as<int64_t>();
  if (v < 0) fail(strf("expected a non-negative integer, got %lld", (long long)v));
  return static_cast<uint64_t>(v);
}
template <>
std::string JsonView::as<std::string>() const {
  if (!value_->is_string()) fail("expected a string, got " + type_name());
  return value_->get<std::string>();
}

std::vector<float> JsonView::floats(size_t n) const {
  if (!value_->is_array() || value_->size() != n) fail(strf("expected an array of %zu numbers", n));
  std::vector<float> out;
  for (size_t i = 0; i < n; ++i) out.push_back(at(i).as<float>());
  return out;
}

glm::vec2 JsonView::as_vec2() const {
  auto f = floats(2);
  return {f[0], f[1]};
}
glm::vec3 JsonView::as_vec3() const {
  auto f = floats(3);
  return {f[0], f[1], f[2]};
}
glm::vec4 JsonView::as_vec4() const {
  auto f = floats(4);
  return {f[0], f[1], f[2], f[3]};
}

float JsonView::as_float_in(float lo, float hi) const {
  float v = as<float>();
  if (v < lo || v > hi) fail(strf("value %g out of range [%g, %g]", v, lo, hi));
  return v;
}

size_t JsonView::as_enum(const std::vector<std::string>& names) const {
  std::string s = as<std::string>();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == s) return i;
  std::string list;
  for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
  fail("unknown value \"" + s + "\" (expected one of: " + list + ")");
}

}  // namespace cumulo
