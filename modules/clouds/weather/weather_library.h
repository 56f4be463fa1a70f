#pragma once
// The shipped weather states: every `*.json` of a folder (default content/weather/), by id (file stem).
//
//   WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
//   const WeatherState& storm = lib.get("storm");   // unknown id: an error listing the known ids
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds::weather {

class WeatherLibrary {
 public:
  static std::filesystem::path default_folder();  // <repo or bundle>/content/weather
  // All states of `folder`; a malformed one fails the load (naming its file and JSON path).
  static WeatherLibrary load(const std::filesystem::path& folder);

  std::vector<std::string> ids() const;  // sorted
  const WeatherState* find(const std::string& id) const;
  const WeatherState& get(const std::string& id) const;  // throws "unknown weather state ... (known: ...)"
  // The same check for data that names a state: throws "WHERE: unknown weather state ... (known: ...)".
  void require(const std::string& id, const std::string& where) const;
  const std::filesystem::path& folder() const { return folder_; }
  // The editor's live edits: adds or replaces the state with s.id; erase removes one (false if absent).
  void put(const WeatherState& s) { states_[s.id] = s; }
  bool erase(const std::string& id) { return states_.erase(id) > 0; }

 private:
  std::filesystem::path folder_;
  std::string unknown(const std::string& id) const;
  std::map<std::string, WeatherState> states_;
};

}  // namespace cumulo::clouds::weather
