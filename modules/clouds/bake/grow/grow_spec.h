#pragma once
// A grow spec: the JSON that `cumulo grow` reads and a recipe's "grown" edit names. A spec starts from
// a preset (one table, kGrowPresets in grow_spec.cpp) and overrides any member of it.
//
//   { "preset": "congestus",                   humilis | mediocris | congestus | cumulonimbus |
//                                              stratocumulus | fractus
//     "seed": 7,
//     "grid": {"cells": [64, 40, 64], "cell": 16},     cells per axis (x, y up, z; multiples of 4) and
//                                                      game metres per cell
//     "scale": 6,                              physical metres per game metre (the atmosphere's scale)
//     "time": {"steps": 260, "dt": 10},        steps of dt physical seconds
//     "atmosphere": {"ground_temperature": 299, "lapse_rate": 7.5, "upper_lapse_rate": 6.5,   K, K/km
//                    "humidity": [0.8, 0.6], "humidity_above": 0.3,         relative, floor -> inversion
//                    "inversion": {"height": 420, "thickness": 40, "strength": 4},   game m, game m, K
//                    "tropopause": 640},                                    game m above the box floor
//     "wind_shear": [1.5, 0],                  m/s of relative wind per physical km (x, z)
//     "vorticity": 0.3,  "condensation_rate": 0.5,
//     "thermals": [{"position": [0, 0], "radius": 260, "heat": 2.5, "moisture": 3, "seed": 1,
//                   "start": 0, "end": 1e9}],   game m from the box centre (x, z); K; g/kg; seconds
//     "decay": {"start": 1800, "rate": 0.002, "humidity": 0.5},    the air dries from `start` (s)
//     "output": {"iso": 0.05} }                cloud-water iso-surface, g/kg
//
// Every error names the spec file and the JSON path ("hero.json: $.grid.cell: expected ...").
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "modules/clouds/bake/grow/solver.h"

namespace cumulo::clouds::grow {

// Bump when a change to the solver, the presets or the output changes the grown bytes: grown clouds
// are cached by (spec content, this), and a committed grown cloud whose key differs is regrown.
inline constexpr const char* kSolverVersion = "grow-2";

struct GrowSpec {
  std::string file;         // for messages
  std::string preset;
  std::string canonical;    // the merged JSON (preset + overrides), compact: what the key hashes
  uint64_t key = 0;         // hash of canonical + kSolverVersion
  SolverSettings solver;    // physical units, cells
  int steps = 0;
  float cell_game = 16.0f;  // game metres per cell
  float scale = 6.0f;       // physical metres per game metre
  float iso = 0.05e-3f;     // kg/kg
};

const std::vector<std::string>& grow_preset_names();

GrowSpec load_grow_spec(const std::filesystem::path& path);
GrowSpec parse_grow_spec_text(const std::string& text, const std::string& name);

// "0123abcd..." (16 hex digits) of spec.key.
std::string grow_key_hex(const GrowSpec& spec);

}  // namespace cumulo::clouds::grow
