#include "engine/core/args.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "engine/core/error.h"

namespace cumulo {
namespace {

double to_double(const std::string& flag, const std::string& s) {
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end || errno) fail("%s: expected a number, got \"%s\"", flag.c_str(), s.c_str());
  return v;
}

long long to_int(const std::string& flag, const std::string& s) {
  char* end = nullptr;
  errno = 0;
  long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end || errno) fail("%s: expected an integer, got \"%s\"", flag.c_str(), s.c_str());
  return v;
}

}  // namespace

ArgParser::ArgParser(std::string command, std::string summary) : command_(std::move(command)), summary_(std::move(summary)) {}

ArgParser& ArgParser::positional(const std::string& name, const std::string& help, std::string* out, bool required) {
  pos_.push_back({name, help, out, required});
  return *this;
}

ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h,
                             std::function<void(const std::string&)> set) {
  opts_.push_back({n, v, h, std::move(set), false});
  return *this;
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, std::string* out) {
  return option(n, v, h, [out](const std::string& s) { *out = s; });
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, int* out) {
  return option(n, v, h, [n, out](const std::string& s) { *out = static_cast<int>(to_int(n, s)); });
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, uint32_t* out) {
  return option(n, v, h, [n, out](const std::string& s) {
    long long x = to_int(n, s);
    if (x < 0 || x > 0xffffffffll) fail("%s: %s is out of range", n.c_str(), s.c_str());
    *out = static_cast<uint32_t>(x);
  });
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, uint64_t* out) {
  return option(n, v, h, [n, out](const std::string& s) {
    long long x = to_int(n, s);
    if (x < 0) fail("%s: %s is out of range", n.c_str(), s.c_str());
    *out = static_cast<uint64_t>(x);
  });
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, float* out) {
  return option(n, v, h, [n, out](const std::string& s) { *out = static_cast<float>(to_double(n, s)); });
}
ArgParser& ArgParser::option(const std::string& n, const std::string& v, const std::string& h, double* out) {
  return option(n, v, h, [n, out](const std::string& s) { *out = to_double(n, s); });
}
ArgParser& ArgParser::flag(const std::string& n, const std::string& h, bool* out) {
  opts_.push_back({n, "", h, [out](const std::string&) { *out = true; }, true});
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
      if (!o) fail("%s: unknown option %s (see %s --help)", command_.c_str(), name.c_str(), command_.c_str());
      if (!o->is_flag && !has_value) {
        if (i + 1 >= argc) fail("%s: %s needs a value (%s)", command_.c_str(), name.c_str(), o->value.c_str());
        value = argv[++i];
      }
      o->set(value);
      set_.push_back(name);
      continue;
    }
    if (next_pos >= pos_.size()) fail("%s: unexpected argument \"%s\" (see %s --help)", command_.c_str(), a.c_str(), command_.c_str());
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
    s += strf("  %-26s %s\n", lhs.c_str(), o.help.c_str());
  }
  s += strf("  %-26s %s\n", "-h, --help", "show this help");
  return s;
}

}  // namespace cumulo
