#include "modules/clouds/bake/grow/grow_spec.h"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/json.h"
#include "engine/core/message.h"

namespace cumulo::clouds::grow {

namespace {

using Json = nlohmann::json;

// The presets: complete specs a file names and overrides. Heights are game metres above the box floor;
// the physics is at `scale` physical metres per game metre. Why each differs:
//  - humilis: a low, strong inversion just above the condensation level caps a flat, wide cloud;
//  - mediocris: the inversion higher, the cloud as tall as wide;
//  - congestus: a weak inversion high up, a moist floor and strong heat: towers;
//  - cumulonimbus: no inversion, a conditionally unstable column up to a tropopause near the box top,
//    above which the air is isothermal (stable): the updraft spreads into an anvil, sheared downwind;
//  - stratocumulus: a strong inversion low over a moist floor heated in many weak cells: a broken sheet;
//  - fractus: a mediocris whose sources stop and whose air dries: a decaying, ragged cloud.
const char* const kGrowPresets = R"json({
 "humilis": {
  "seed": 1, "grid": {"cells": [56, 24, 56], "cell": 12}, "scale": 6, "time": {"steps": 200, "dt": 10},
  "atmosphere": {"ground_temperature": 299, "lapse_rate": 6.6, "upper_lapse_rate": 6.0, "humidity": [0.85, 0.55],
                 "humidity_above": 0.3, "inversion": {"height": 150, "thickness": 24, "strength": 6}, "tropopause": 100000},
  "wind_shear": [1.0, 0], "vorticity": 0.3, "condensation_rate": 0.5,
  "thermals": [{"position": [0, 0], "radius": 220, "heat": 2.0, "moisture": 2.5, "seed": 1, "start": 0, "end": 1e9}],
  "decay": {"start": 1e9, "rate": 0, "humidity": 0.5}, "output": {"iso": 0.1}},
 "mediocris": {
  "seed": 1, "grid": {"cells": [56, 36, 56], "cell": 14}, "scale": 6, "time": {"steps": 240, "dt": 10},
  "atmosphere": {"ground_temperature": 299, "lapse_rate": 6.6, "upper_lapse_rate": 6.0, "humidity": [0.85, 0.5],
                 "humidity_above": 0.3, "inversion": {"height": 300, "thickness": 30, "strength": 6}, "tropopause": 100000},
  "wind_shear": [1.0, 0], "vorticity": 0.3, "condensation_rate": 0.5,
  "thermals": [{"position": [0, 0], "radius": 280, "heat": 2.5, "moisture": 3.0, "seed": 1, "start": 0, "end": 1e9}],
  "decay": {"start": 1e9, "rate": 0, "humidity": 0.5}, "output": {"iso": 0.1}},
 "congestus": {
  "seed": 1, "grid": {"cells": [64, 40, 64], "cell": 16}, "scale": 6, "time": {"steps": 260, "dt": 10},
  "atmosphere": {"ground_temperature": 299, "lapse_rate": 6.6, "upper_lapse_rate": 6.0, "humidity": [0.85, 0.5],
                 "humidity_above": 0.3, "inversion": {"height": 520, "thickness": 40, "strength": 4}, "tropopause": 100000},
  "wind_shear": [1.0, 0], "vorticity": 0.3, "condensation_rate": 0.5,
  "thermals": [{"position": [0, 0], "radius": 380, "heat": 2.5, "moisture": 3.0, "seed": 1, "start": 0, "end": 1e9}],
  "decay": {"start": 1e9, "rate": 0, "humidity": 0.5}, "output": {"iso": 0.1}},
 "cumulonimbus": {
  "seed": 1, "grid": {"cells": [68, 52, 60], "cell": 20}, "scale": 6, "time": {"steps": 300, "dt": 10},
  "atmosphere": {"ground_temperature": 299, "lapse_rate": 6.6, "upper_lapse_rate": 6.6, "humidity": [0.85, 0.58],
                 "humidity_above": 0.55, "inversion": {"height": 100000, "thickness": 40, "strength": 0}, "tropopause": 800},
  "wind_shear": [0.8, 0.2], "vorticity": 0.3, "condensation_rate": 0.5,
  "thermals": [{"position": [-150, 0], "radius": 370, "heat": 2.8, "moisture": 3.7, "seed": 1, "start": 0, "end": 1e9}],
  "decay": {"start": 1e9, "rate": 0, "humidity": 0.5}, "output": {"iso": 0.1}},
 "stratocumulus": {
  "seed": 1, "grid": {"cells": [80, 20, 80], "cell": 14}, "scale": 6, "time": {"steps": 220, "dt": 10},
  "atmosphere": {"ground_temperature": 295, "lapse_rate": 7.0, "upper_lapse_rate": 6.5, "humidity": [0.9, 0.85],
                 "humidity_above": 0.25, "inversion": {"height": 150, "thickness": 20, "strength": 7}, "tropopause": 100000},
  "wind_shear": [1.5, 0], "vorticity": 0.3, "condensation_rate": 0.5,
  "thermals": [{"position": [0, 0], "radius": 540, "heat": 1.2, "moisture": 2.0, "seed": 1, "start": 0, "end": 1e9}],
  "decay": {"start": 1e9, "rate": 0, "humidity": 0.5}, "output": {"iso": 0.1}},
 "fractus": {
  "seed": 1, "grid": {"cells": [56, 36, 56], "cell": 14}, "scale": 6, "time": {"steps": 260, "dt": 10},
  "atmosphere": {"ground_temperature": 299, "lapse_rate": 6.6, "upper_lapse_rate": 6.0, "humidity": [0.85, 0.5],
                 "humidity_above": 0.3, "inversion": {"height": 300, "thickness": 30, "strength": 6}, "tropopause": 100000},
  "wind_shear": [2.0, 0], "vorticity": 0.35, "condensation_rate": 0.5,
  "thermals": [{"position": [0, 0], "radius": 300, "heat": 2.6, "moisture": 3.2, "seed": 1, "start": 0, "end": 2300}],
  "decay": {"start": 2300, "rate": 0.0007, "humidity": 0.9}, "output": {"iso": 0.1}}
})json";

const Json& presets() {
  static const Json p = Json::parse(kGrowPresets);
  return p;
}

// Objects merge member by member; arrays and scalars replace (a spec's "thermals" is its own list).
void merge(Json& base, const Json& over) {
  for (auto it = over.begin(); it != over.end(); ++it) {
    if (it->is_object() && base.contains(it.key()) && base[it.key()].is_object())
      merge(base[it.key()], *it);
    else
      base[it.key()] = *it;
  }
}

void check_keys(const JsonView& v, const std::set<std::string>& allowed) {
  if (!v.is_object()) v.fail("expected an object");
  for (const std::string& k : v.keys())
    if (!allowed.count(k)) v[k].fail("unknown member " + quote(k, 64));
}

float number_in(const JsonView& v, float lo, float hi) { return v.as_float_in(lo, hi); }

GrowSpec parse(const JsonView& user, const std::string& file) {
  if (!user.is_object()) user.fail("expected a grow spec object");
  check_keys(user, {"$schema", "comment", "preset", "seed", "grid", "scale", "time", "atmosphere", "wind_shear",
                    "vorticity", "condensation_rate", "thermals", "decay", "output"});
  GrowSpec s;
  s.file = file;
  s.preset = user.has("preset") ? grow_preset_names()[user["preset"].as_enum(grow_preset_names())] : "mediocris";
  Json merged = presets()[s.preset];
  Json over = user.raw();
  over.erase("$schema");
  over.erase("comment");
  over.erase("preset");
  merge(merged, over);
  s.canonical = Json{{"preset", s.preset}, {"spec", merged}}.dump();
  s.key = hash64(std::string_view(kSolverVersion), hash64(s.canonical));

  JsonDocument doc(merged, file);
  const JsonView r = doc.view();
  SolverSettings& o = s.solver;
  o.seed = r["seed"].as<uint64_t>();

  const JsonView grid = r["grid"];
  check_keys(grid, {"cells", "cell"});
  for (int a = 0; a < 3; ++a) {
    const JsonView c = grid["cells"].at(a);
    const float v = c.as_float_in(8, 512);
    if (std::floor(v) != v || int(v) % 4 != 0) c.fail(strf("expected a multiple of 4 in 8..512, got %g", v));
    o.dims[a] = int(v);
  }
  if (grid["cells"].size() != 3) grid["cells"].fail("expected [x, y, z]");
  s.cell_game = number_in(grid["cell"], 0.5f, 256.0f);
  s.scale = number_in(r["scale"], 0.1f, 100.0f);
  o.cell = s.cell_game * s.scale;

  const JsonView time = r["time"];
  check_keys(time, {"steps", "dt"});
  s.steps = int(number_in(time["steps"], 1, 100000));
  o.dt = number_in(time["dt"], 0.01f, 600.0f);

  const JsonView a = r["atmosphere"];
  check_keys(a, {"ground_temperature", "lapse_rate", "upper_lapse_rate", "humidity", "humidity_above", "inversion",
                 "tropopause"});
  AtmosphereSettings& at = o.atmosphere;
  at.ground_temperature = number_in(a["ground_temperature"], 200.0f, 340.0f);
  at.lapse_rate = number_in(a["lapse_rate"], -20.0f, 9.8f) * 1e-3f;
  at.upper_lapse_rate = number_in(a["upper_lapse_rate"], -20.0f, 9.8f) * 1e-3f;
  const glm::vec2 hum = a["humidity"].as_vec2();
  for (int i = 0; i < 2; ++i) a["humidity"].at(i).as_float_in(0.0f, 1.0f);
  at.humidity_ground = hum.x, at.humidity_top = hum.y;
  at.humidity_above_inversion = number_in(a["humidity_above"], 0.0f, 1.0f);
  const JsonView inv = a["inversion"];
  check_keys(inv, {"height", "thickness", "strength"});
  at.inversion_height = number_in(inv["height"], 0.0f, 1e6f) * s.scale;
  at.inversion_thickness = number_in(inv["thickness"], 0.1f, 1e5f) * s.scale;
  at.inversion_strength = number_in(inv["strength"], 0.0f, 40.0f);
  at.tropopause_height = number_in(a["tropopause"], 0.0f, 1e6f) * s.scale;

  o.wind_shear = r["wind_shear"].as_vec2();
  for (int i = 0; i < 2; ++i) r["wind_shear"].at(i).as_float_in(-50.0f, 50.0f);
  o.vorticity = number_in(r["vorticity"], 0.0f, 2.0f);
  o.condensation_rate = number_in(r["condensation_rate"], 0.01f, 1.0f);

  const glm::vec2 centre(o.dims.x * 0.5f, o.dims.z * 0.5f);
  const auto thermals = r["thermals"].elements();
  if (thermals.empty() || thermals.size() > 64) r["thermals"].fail("expected 1..64 thermals");
  for (const JsonView& t : thermals) {
    check_keys(t, {"position", "radius", "heat", "moisture", "seed", "start", "end", "comment"});
    Thermal th;
    const glm::vec2 p = t["position"].as_vec2();
    for (int i = 0; i < 2; ++i) t["position"].at(i).as_float_in(-1e5f, 1e5f);
    th.position = centre + p / s.cell_game;
    if (th.position.x < 0.0f || th.position.y < 0.0f || th.position.x > float(o.dims.x) || th.position.y > float(o.dims.z))
      t["position"].fail(strf("outside the grid's floor (x and z within +-%g and +-%g game m of its centre)",
                              0.5f * o.dims.x * s.cell_game, 0.5f * o.dims.z * s.cell_game));
    th.radius = number_in(t["radius"], 0.1f, 1e5f) / s.cell_game;
    if (th.radius < 1.0f) t["radius"].fail(strf("a thermal narrower than a cell (%g game m per cell)", s.cell_game));
    th.heat = number_in(t["heat"], 0.0f, 20.0f);
    th.moisture = number_in(t["moisture"], 0.0f, 30.0f);
    th.seed = t.get<uint32_t>("seed", 1);
    th.start = t.has("start") ? number_in(t["start"], 0.0f, 1e9f) : 0.0f;
    th.end = t.has("end") ? number_in(t["end"], 0.0f, 1e9f) : 1e9f;
    if (th.end < th.start) t["end"].fail("a thermal ends before it starts");
    o.thermals.push_back(th);
  }
  const JsonView d = r["decay"];
  check_keys(d, {"start", "rate", "humidity"});
  o.drying_start = number_in(d["start"], 0.0f, 1e9f);
  o.drying_rate = number_in(d["rate"], 0.0f, 1.0f);
  o.drying_humidity = number_in(d["humidity"], 0.0f, 1.0f);
  const JsonView out = r["output"];
  check_keys(out, {"iso"});
  s.iso = number_in(out["iso"], 1e-4f, 10.0f) * 1e-3f;
  return s;
}

}  // namespace

const std::vector<std::string>& grow_preset_names() {
  static const std::vector<std::string> names = {"humilis", "mediocris", "congestus", "cumulonimbus", "stratocumulus",
                                                 "fractus"};
  return names;
}

GrowSpec load_grow_spec(const std::filesystem::path& path) {
  JsonDocument doc = load_json_file(path);
  return parse(doc.view(), path.string());
}

GrowSpec parse_grow_spec_text(const std::string& text, const std::string& name) {
  JsonDocument doc = parse_json_text(text, name);
  return parse(doc.view(), name);
}

std::string grow_key_hex(const GrowSpec& spec) {
  char key[17];
  std::snprintf(key, sizeof key, "%016llx", static_cast<unsigned long long>(spec.key));
  return key;
}

}  // namespace cumulo::clouds::grow
