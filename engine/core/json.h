#pragma once
// JSON loading with errors that name the file, the line/column of a syntax error, or the JSON path
// ($.entities[3].transform.position) of a value of the wrong type or range.
//
//   JsonDocument doc = load_json_file("level.json");
//   JsonView root = doc.view();
//   float t = root["sun"].get<float>("hours", 12.0f);   // optional with default
//   std::string name = root["name"].as<std::string>();   // required, type checked
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "engine/core/enum_names.h"
#include "engine/core/error.h"

namespace cumulo {

using Json = nlohmann::json;

class JsonView {
 public:
  JsonView(const Json* value, std::shared_ptr<const std::string> file, std::string path)
      : value_(value), file_(std::move(file)), path_(std::move(path)) {}

  const Json& raw() const { return *value_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }

  bool is_object() const { return value_->is_object(); }
  bool is_array() const { return value_->is_array(); }
  bool has(const std::string& key) const { return value_->is_object() && value_->contains(key); }
  size_t size() const;  // array length or object size; fails on scalars

  JsonView operator[](const std::string& key) const;  // required member
  JsonView at(size_t index) const;                     // required array element
  std::vector<JsonView> elements() const;              // array elements (fails if not an array)
  std::vector<std::string> keys() const;               // object keys in document order

  // bool, int, int64_t, uint32_t, uint64_t, float, double, std::string. Numbers follow the one rule
  // of core/number.h: finite and in range of T (1e39 is not a float, 4294967312 not a uint32_t).
  template <typename T>
  T as() const;
  template <typename T>
  T get(const std::string& key) const {
    return (*this)[key].template as<T>();
  }
  template <typename T>
  T get(const std::string& key, T fallback) const {
    return has(key) ? (*this)[key].template as<T>() : fallback;
  }

  glm::vec2 as_vec2() const;
  glm::vec3 as_vec3() const;
  glm::vec4 as_vec4() const;
  glm::vec3 get_vec3(const std::string& key, glm::vec3 fallback) const {
    return has(key) ? (*this)[key].as_vec3() : fallback;
  }
  // A number that must lie in [lo, hi].
  float as_float_in(float lo, float hi) const;
  // A string from a fixed set; returns its index.
  size_t as_enum(const std::vector<std::string>& names) const;
  // One of a name table's names (engine/core/enum_names.h); its value.
  template <typename E, size_t N>
  E as_name(const std::array<EnumName<E>, N>& table) const {
    std::vector<std::string> names;
    for (const EnumName<E>& row : table) names.push_back(row.name);
    return table[as_enum(names)].value;
  }

  // "FILE: $.path: MESSAGE"
  [[noreturn]] void fail(const std::string& message) const;
  std::string where() const;

 private:
  std::string type_name() const;
  std::vector<float> floats(size_t n) const;
  template <typename T>
  T integer() const;

  const Json* value_;
  std::shared_ptr<const std::string> file_;
  std::string path_;
};

class JsonDocument {
 public:
  JsonDocument(Json root, std::string file)
      : root_(std::make_shared<Json>(std::move(root))), file_(std::make_shared<const std::string>(std::move(file))) {}
  JsonView view() const { return JsonView(root_.get(), file_, "$"); }
  const Json& json() const { return *root_; }
  const std::string& file() const { return *file_; }

 private:
  std::shared_ptr<Json> root_;
  std::shared_ptr<const std::string> file_;
};

// Throws cumulo::Error "FILE:LINE:COL: JSON syntax error: ..." or "FILE: cannot open: ...". Every
// parse refuses, with the line and column: text nested deeper than 256 levels (checked before any
// parser runs) and numbers that overflow a double ("FILE:L:C: $.a.b: number 1e999999 does not fit...").
JsonDocument load_json_file(const std::filesystem::path& path);
JsonDocument parse_json_text(const std::string& text, const std::string& name);
// The same checks without building a document: the gate in front of other JSON readers (tinygltf),
// so they only ever see text that our rules accept.
void check_json_text(std::string_view text, const std::string& name);

}  // namespace cumulo
