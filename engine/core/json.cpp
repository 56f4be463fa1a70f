#include "engine/core/json.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

#include "engine/core/file_io.h"
#include "engine/core/message.h"
#include "engine/core/number.h"

namespace cumulo {

namespace {

// Deep enough for any real document; shallow enough that recursive consumers (tinygltf's value
// conversion, our own visitors) cannot exhaust the stack on hostile input.
constexpr size_t kMaxJsonDepth = 256;

// 1-based line and column of a 0-based byte offset.
std::string location(std::string_view text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return strf("%zu:%zu", line, col);
}

// Offset of the first '[' or '{' nested deeper than kMaxJsonDepth (outside strings), or npos. Run
// before any parser, so the limit holds for every consumer of the text, whatever its own recursion.
size_t too_deep_at(std::string_view text) {
  size_t depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

struct ParseFailure {
  size_t position;  // bytes read: points just past the offending character
  std::string token, what, path;
  int id;  // nlohmann's exception id (101..: syntax, 406: number overflow)
};

// nlohmann's SAX events forwarded to `Builder` (the DOM builder, or the acceptor that builds nothing),
// keeping the JSON path of the value being read: nlohmann reports some errors (a number that overflows
// a double) with a byte offset only, and our messages name the path too.
template <typename Builder>
class PathSax {
 public:
  explicit PathSax(Builder& builder) : b_(builder) {}

  bool null() { return value(b_.null()); }
  bool boolean(bool v) { return value(b_.boolean(v)); }
  bool number_integer(Json::number_integer_t v) { return value(b_.number_integer(v)); }
  bool number_unsigned(Json::number_unsigned_t v) { return value(b_.number_unsigned(v)); }
  bool number_float(Json::number_float_t v, const Json::string_t& s) { return value(b_.number_float(v, s)); }
  bool string(Json::string_t& v) { return value(b_.string(v)); }
  bool binary(Json::binary_t& v) { return value(b_.binary(v)); }
  bool start_object(size_t n) {
    frames_.push_back({false, 0, {}});
    return b_.start_object(n);
  }
  bool key(Json::string_t& k) {
    frames_.back().key = k;
    return b_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return value(b_.end_object());
  }
  bool start_array(size_t n) {
    frames_.push_back({true, 0, {}});
    return b_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return value(b_.end_array());
  }
  bool parse_error(size_t position, const std::string& token, const nlohmann::detail::exception& e) {
    error_ = ParseFailure{position, token, e.what(), path(), e.id};
    return false;
  }

  const std::optional<ParseFailure>& error() const { return error_; }

 private:
  struct Frame {
    bool array;
    size_t index;     // array: elements completed so far
    std::string key;  // object: the member being read
  };
  bool value(bool ok) {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return ok;
  }
  std::string path() const {
    std::string p = "$";
    for (const Frame& f : frames_) p += f.array ? strf("[%zu]", f.index) : "." + clip(f.key, 64);
    return p;
  }

  Builder& b_;
  std::vector<Frame> frames_;
  std::optional<ParseFailure> error_;
};

// Parses `text` into `out` (or only checks it when `out` is null); throws the one-line error.
void parse_checked(std::string_view text, const std::string& name, Json* out) {
  if (size_t at = too_deep_at(text); at != std::string_view::npos)
    fail("%s:%s: JSON nested deeper than %zu levels", name.c_str(), location(text, at).c_str(), kMaxJsonDepth);
  std::optional<ParseFailure> failure;
  if (out) {
    nlohmann::detail::json_sax_dom_parser<Json> dom(*out, /*allow_exceptions=*/false);
    PathSax sax(dom);
    if (!Json::sax_parse(text.begin(), text.end(), &sax)) failure = sax.error();
  } else {
    nlohmann::detail::json_sax_acceptor<Json> acceptor;
    PathSax sax(acceptor);
    if (!Json::sax_parse(text.begin(), text.end(), &sax)) failure = sax.error();
  }
  if (!failure) return;
  const std::string where = name + ":" + location(text, failure->position > 0 ? failure->position - 1 : 0);
  if (failure->id == 406)  // nlohmann: "number overflow parsing '1e999999'"
    fail("%s: %s: number %s does not fit a 64-bit float (|x| <= 1.8e308)", where.c_str(), failure->path.c_str(),
         clip(failure->token, 40).c_str());
  if (failure->id >= 100 && failure->id < 200) {
    // "[json.exception.parse_error.101] parse error at line L, column C: DETAIL" -> DETAIL
    std::string detail = library_message(failure->what);
    if (auto colon = detail.find(": ", detail.find("parse error")); colon != std::string::npos)
      detail = detail.substr(colon + 2);
    fail("%s: JSON syntax error: %s", where.c_str(), detail.c_str());
  }
  fail("%s: %s: %s", where.c_str(), failure->path.c_str(), library_message(failure->what).c_str());
}

}  // namespace

JsonDocument parse_json_text(const std::string& text, const std::string& name) {
  Json root;
  parse_checked(text, name, &root);
  return JsonDocument(std::move(root), name);
}

void check_json_text(std::string_view text, const std::string& name) { parse_checked(text, name, nullptr); }

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
  if (it == value_->end()) fail("missing required member " + quote(key, 64));
  return JsonView(&*it, file_, path_ + "." + clip(key, 64));
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
  return narrow_number<double>(value_->get<double>(), [this](const std::string& why) { fail(why); });
}
template <>
float JsonView::as<float>() const {
  if (!value_->is_number()) fail("expected a number, got " + type_name());
  return narrow_number<float>(value_->get<double>(), [this](const std::string& why) { fail(why); });
}
// JSON integers are read exactly (64-bit signed or unsigned); a float is accepted when it is whole.
template <typename T>
T JsonView::integer() const {
  std::optional<std::string> why;
  if (value_->is_number_unsigned()) why = integer_problem<T>(value_->get<uint64_t>());
  else if (value_->is_number_integer()) why = integer_problem<T>(value_->get<int64_t>());
  else if (value_->is_number_float()) why = number_problem<T>(value_->get<double>());
  else fail("expected an integer, got " + type_name());
  if (why) fail(*why);
  if (value_->is_number_unsigned()) return static_cast<T>(value_->get<uint64_t>());
  if (value_->is_number_integer()) return static_cast<T>(value_->get<int64_t>());
  return static_cast<T>(value_->get<double>());
}
template <>
int64_t JsonView::as<int64_t>() const {
  return integer<int64_t>();
}
template <>
int JsonView::as<int>() const {
  return integer<int>();
}
template <>
uint32_t JsonView::as<uint32_t>() const {
  return integer<uint32_t>();
}
template <>
uint64_t JsonView::as<uint64_t>() const {
  return integer<uint64_t>();
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
  fail("unknown value " + quote(s) + " (expected one of: " + list + ")");
}

}  // namespace cumulo
