#pragma once
// The editable parameters of a weather state, one per JSON key the editor shows: the UI builds its
// widgets from this list and scripts name parameters by its `path` (the stable dotted JSON keys of
// weather_state.h). The list is the rows of the weather's field table (weather_fields.h) that have a
// group, so a key added there shows up here with nothing else to do.
//
//   const ParamInfo* p = find_param("lighting.absorption");   // nullptr for an unknown path
//   Json v = get_param(doc.json("storm"), p->path);             // throws naming the path when missing
//   set_param(copy, "wind.speed", 12);                          // creates missing objects on the way
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/json.h"
#include "modules/clouds/weather/weather_fields.h"

namespace cumulo::editor {

using ParamKind = clouds::weather::FieldType;  // Float, Int, Vec3, Text

struct ParamInfo {
  std::string path;     // dotted JSON key: "coverage", "lighting.phase.forward"
  std::string label;    // short, for a widget
  std::string tooltip;  // one sentence: what it does to the sky
  ParamKind kind = ParamKind::Float;
  double min = 0.0, max = 1.0;  // the loader's range (Vec3: per component, a UI range only; Text: unused)
  std::string group;            // "Clouds", "Wind", "Cloud map", "Lighting", "Weather"
  // An optional key (a state may leave it out; the loader then takes the default): its default, which the panel
  // shows and edits from when the state has none. Null for required keys.
  Json default_value;
};

// In the order the UI shows them (grouped).
const std::vector<ParamInfo>& weather_params();
const ParamInfo* find_param(std::string_view path);
// The groups in display order (that of their first rows in the table).
const std::vector<std::string>& weather_param_groups();

// Throws cumulo::Error "PATH: no such key in the state" when a part of the path is missing.
Json get_param(const Json& state, std::string_view path);
// Sets the value, creating objects on the way (the loader then decides whether the result is valid).
void set_param(Json& state, std::string_view path, const Json& value);

// Whether `value` has the parameter's JSON type and lies in its range; the reason when not
// ("1.5 is out of range [0, 1]"; callers prefix the state and the path). A number of a Float parameter must be finite.
std::optional<std::string> check_param_value(const ParamInfo& p, const Json& value);
// Floats from a slider are doubles of a float (0.449999988079071); stored as the shortest decimal that
// reads back as the same float (0.45), so saved files stay readable and diff cleanly. Other kinds and
// non-numbers are returned unchanged.
Json normalize_param_value(const ParamInfo& p, const Json& value);

}  // namespace cumulo::editor
