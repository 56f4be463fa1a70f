#pragma once
// Shared by the editor model's tests: a copy of the shipped weather states in a temporary folder, and a
// map maker that needs no GPU.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "editor/model/weather_document.h"
#include "engine/core/file_io.h"
#include "engine/core/png.h"
#include "tests/support/temp_dir.h"

namespace cumulo::editor::test {

inline std::filesystem::path shipped_weather() { return repo_root() / "content" / "weather"; }

// The shipped *.json states, copied into `dir`.
inline void copy_shipped_weather(const std::filesystem::path& dir) {
  for (const auto& e : std::filesystem::directory_iterator(shipped_weather()))
    if (e.path().extension() == ".json") std::filesystem::copy_file(e.path(), dir / e.path().filename());
}

// The PNG when the source names one; else a small map whose coverage follows the seed (deterministic).
inline PaintedCloudMap fake_map(const clouds::weather::CloudMapSource& src) {
  PaintedCloudMap m;
  if (!src.png.empty()) {
    ImageRgba8 img = read_png_rgba8(src.png);
    return {img.width, img.height, std::move(img.rgba)};
  }
  m.width = 32;
  m.height = 16;
  m.rgba.resize(size_t(m.width) * m.height * 4);
  for (uint32_t i = 0; i < m.width * m.height; ++i) {
    m.rgba[i * 4 + 0] = uint8_t((i * 7 + src.seed * 13) % 256);
    m.rgba[i * 4 + 1] = 128;
    m.rgba[i * 4 + 2] = 128;
    m.rgba[i * 4 + 3] = 255;
  }
  return m;
}

// Another program's save: new bytes and an mtime the watch cannot mistake for the old one (a file
// system's clock ticks coarser than a test runs).
inline void external_write(const std::filesystem::path& path, const std::string& text) {
  std::error_code ec;
  const auto before = std::filesystem::last_write_time(path, ec);
  write_file_atomic(path, text);
  if (!ec) std::filesystem::last_write_time(path, before + std::chrono::seconds(2));
}

inline bool running_as_root() { return ::geteuid() == 0; }

}  // namespace cumulo::editor::test
