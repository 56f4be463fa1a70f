#include "engine/core/args.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <type_traits>

#include "engine/core/error.h"
#include "engine/core/message.h"
#include "engine/core/number.h"

namespace cumulo {
template <typename T>
T parse_flag_number(const std::string& flag, const std::string& text) {
  const char* kind = std::is_floating_point_v<T> ? "a number" : "an integer";
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])))
    fail("%s: expected %s, got %s", flag.c_str(), kind, quote(text).c_str());
  char* end = nullptr;
  errno = 0;
  std::optional<std::string> why;
  T out{};
  if constexpr (std::is_floating_point_v<T>) {
    // Overflow (ERANGE with +-HUGE_VAL) is left to the rule, which names it; underflow to 0 or a
    // denormal is a value like any other.
    const double v = std::strtod(text.c_str(), &end);
    if (*end) fail("%s: expected %s, got %s", flag.c_str(), kind, quote(text).c_str());
    why = number_problem<T>(v);
    out = static_cast<T>(v);
  } else if constexpr (std::is_signed_v<T>) {
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (*end) fail("%s: expected %s, got %s", flag.c_str(), kind, quote(text).c_str());
    why = errno == ERANGE ? strf("%s does not fit %s", clip(text).c_str(), number_type_name<T>()) : integer_problem<T>(v);
    out = static_cast<T>(v);
  } else {
    // strtoull accepts "-1" and wraps it; a sign is never a valid unsigned value.
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (*end) fail("%s: expected %s, got %s", flag.c_str(), kind, quote(text).c_str());
    if (text[0] == '-' || errno == ERANGE) why = strf("%s does not fit %s", clip(text).c_str(), number_type_name<T>());
    else why = integer_problem<T>(v);
    out = static_cast<T>(v);
  }
  if (why) fail("%s: %s", flag.c_str(), why->c_str());
  return out;
}

template <typename T>
std::vector<T> parse_flag_list(const std::string& flag, const std::string& text, size_t n) {
  std::vector<T> out;
  size_t start = 0;
  while (out.size() <= n) {
    const size_t comma = text.find(',', start);
    out.push_back(parse_flag_number<T>(flag, text.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() != n) fail("%s: expected %zu comma-separated numbers, got %s", flag.c_str(), n, quote(text).c_str());
  return out;
}

#define CUMULO_ARGS_NUMBER(T)                                                      \
  template T parse_flag_number<T>(const std::string&, const std::string&);        \
  template std::vector<T> parse_flag_list<T>(const std::string&, const std::string&, size_t);
CUMULO_ARGS_NUMBER(int)
CUMULO_ARGS_NUMBER(uint32_t)
CUMULO_ARGS_NUMBER(uint64_t)
CUMULO_ARGS_NUMBER(float)
CUMULO_ARGS_NUMBER(double)
#undef CUMULO_ARGS_NUMBER

namespace {

std::string range_text(double lo, double hi, Open open) {
  const bool lo_open = open == Open::Low || open == Open::Both, hi_open = open == Open::High || open == Open::Both;
  if (std::isinf(hi)) return strf("%s %g", lo_open ? ">" : ">=", lo);
  if (std::isinf(lo)) return strf("%s %g", hi_open ? "<" : "<=", hi);
  if (!lo_open && !hi_open) return strf("%g..%g", lo, hi);
  return strf("%g %s x %s %g", lo, lo_open ? "<" : "<=", hi_open ? "<" : "<=", hi);
}

}  // namespace

ArgParser::ArgParser(std::string command, std::string summary) : command_(std::move(command)), summary_(std::move(summary)) {}

ArgParser& ArgParser::positional(const std::string& name, const std::string& help, std::string* out, bool required) {
  pos_.push_back({name, help, out, required});
  return *this;
}

ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h,
                             std::function<void(const std::string&)> set) {
  opts_.push_back({n, v, h, [set = std::move(set)](const std::string& s, const Opt&) { set(s); }, false, {}});
  return *this;
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, std::string* out) {
  return option(n, v, h, [out](const std::string& s) { *out = s; });
}

template <typename T>
ArgParser& ArgParser::number_option(const std::string& n, const std::string& v, const std::string& h, T* out) {
  opts_.push_back({n, v, h, [out](const std::string& s, const Opt& o) {
                     const T x = parse_flag_number<T>(o.name, s);
                     const Range& r = o.range;
                     const bool lo_open = r.open == Open::Low || r.open == Open::Both;
                     const bool hi_open = r.open == Open::High || r.open == Open::Both;
                     const double d = double(x);
                     if (r.set && ((lo_open ? !(d > r.lo) : !(d >= r.lo)) || (hi_open ? !(d < r.hi) : !(d <= r.hi))))
                       fail("%s: %s is out of range (expected %s)", o.name.c_str(), clip(s).c_str(),
                            range_text(r.lo, r.hi, r.open).c_str());
                     *out = x;
                   },
                   false, {}});
  return *this;
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, int* out) {
  return number_option(n, v, h, out);
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, uint32_t* out) {
  return number_option(n, v, h, out);
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, uint64_t* out) {
  return number_option(n, v, h, out);
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, float* out) {
  return number_option(n, v, h, out);
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, double* out) {
  return number_option(n, v, h, out);
}
ArgParser& ArgParser::flag(const std::string& n, const std::string& h, bool* out) {
  opts_.push_back({n, "", h, [out](const std::string&, const Opt&) { *out = true; }, true, {}});
  return *this;
}
ArgParser& ArgParser::range(double lo, double hi, Open open) {
  if (opts_.empty() || opts_.back().is_flag) fail("%s: range() must follow a numeric option", command_.c_str());
  opts_.back().range = {lo, hi, open, true};
  return *this;
}

const ArgParser::Opt* ArgParser::find(const std::string& name) const {
  for (auto& o : opts_)
    if (o.name == name) return &o;
  return nullptr;
}

bool ArgParser::was_set(const std::string& name) const {
  return std::find(set_.begin(), set_.end(), name) != set_.end();
}

bool ArgParser::parse(int argc, char** argv) {
  size_t next_pos = 0;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf("%s", help().c_str());
      return false;
    }
    if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit((unsigned char)a[1]) || a[1] == '.'))) {
      std::string name = a, value;
      bool has_value = false;
      if (auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
        name = a.substr(0, eq);
        value = a.substr(eq + 1);
        has_value = true;
      }
      const Opt* o = find(name);
      if (!o) fail("%s: unknown option %s (see %s --help)", command_.c_str(), clip(name).c_str(), command_.c_str());
      if (!o->is_flag && !has_value) {
        if (i + 1 >= argc) fail("%s: %s needs a value (%s)", command_.c_str(), name.c_str(), o->value.c_str());
        value = argv[++i];
      }
      o->set(value, *o);
      set_.push_back(name);
      continue;
    }
    if (next_pos >= pos_.size())
      fail("%s: unexpected argument %s (see %s --help)", command_.c_str(), quote(a).c_str(), command_.c_str());
    *pos_[next_pos++].out = a;
  }
  for (size_t k = next_pos; k < pos_.size(); ++k)
    if (pos_[k].required) fail("%s: missing %s (see %s --help)", command_.c_str(), pos_[k].name.c_str(), command_.c_str());
  return true;
}

std::string ArgParser::help() const {
  std::string s = "usage: " + command_;
  for (auto& p : pos_) s += p.required ? " " + p.name : " [" + p.name + "]";
  if (!opts_.empty()) s += " [options]";
  s += "\n\n" + summary_ + "\n";
  if (!pos_.empty()) {
    s += "\narguments:\n";
    for (auto& p : pos_) s += strf("  %-26s %s\n", p.name.c_str(), p.help.c_str());
  }
  s += "\noptions:\n";
  for (auto& o : opts_) {
    std::string lhs = o.name + (o.value.empty() ? "" : " " + o.value);
    std::string help = o.help;
    if (o.range.set) help += " [" + range_text(o.range.lo, o.range.hi, o.range.open) + "]";
    s += strf("  %-26s %s\n", lhs.c_str(), help.c_str());
  }
  s += strf("  %-26s %s\n", "-h, --help", "show this help");
  return s;
}

}  // namespace cumulo
