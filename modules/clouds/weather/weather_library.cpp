#include "modules/clouds/weather/weather_library.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

namespace cumulo::clouds::weather {

std::filesystem::path WeatherLibrary::default_folder() { return repo_root() / "content/weather"; }

WeatherLibrary WeatherLibrary::load(const std::filesystem::path& folder) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) fail("%s: no such folder of weather states", folder.string().c_str());
  // An editor killed in the middle of a save: its set is finished (or undone) before any state is read.
  for (const std::string& line : recover_file_sets(folder)) LOG_INFO("%s", line.c_str());
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  if (ec) fail("%s: cannot list the weather states: %s", folder.string().c_str(), ec.message().c_str());
  std::sort(files.begin(), files.end());
  WeatherLibrary lib;
  lib.folder_ = folder;
  for (const auto& f : files) {
    WeatherState s = load_weather_state(f);
    lib.states_.emplace(s.id, std::move(s));
  }
  if (lib.states_.empty()) fail("%s: no weather states (*.json) in this folder", folder.string().c_str());
  return lib;
}

std::vector<std::string> WeatherLibrary::ids() const {
  std::vector<std::string> out;
  for (const auto& [id, s] : states_) out.push_back(id);
  return out;
}

const WeatherState* WeatherLibrary::find(const std::string& id) const {
  auto it = states_.find(id);
  return it == states_.end() ? nullptr : &it->second;
}

std::string WeatherLibrary::unknown(const std::string& id) const {
  std::string known;
  for (const std::string& k : ids()) known += (known.empty() ? "" : ", ") + k;
  return strf("unknown weather state \"%s\" (known in %s: %s)", id.c_str(), folder_.string().c_str(), known.c_str());
}

const WeatherState& WeatherLibrary::get(const std::string& id) const {
  if (const WeatherState* s = find(id)) return *s;
  fail("%s", unknown(id).c_str());
}

void WeatherLibrary::require(const std::string& id, const std::string& where) const {
  if (!find(id)) fail("%s: %s", where.c_str(), unknown(id).c_str());
}

}  // namespace cumulo::clouds::weather
