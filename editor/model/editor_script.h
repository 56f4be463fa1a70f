#pragma once
// Editor scripts (`cumulo edit --script FILE`): a JSON array of actions the editor performs one per
// frame, for tests, screenshots and bug reports. Everything is checked when the file is loaded, so a
// script fails before it has changed anything: unknown keys or actions, missing keys, wrong types and
// out-of-range numbers throw cumulo::Error "FILE: $[i]...: message" (an unknown action lists the known).
//
//   [{"do": "select_state", "name": "storm"},
//    {"do": "set", "param": "coverage", "value": 0.8},
//    {"do": "paint", "channel": "coverage", "x": 0.5, "y": 0.5, "radius": 0.1, "value": 0},
//    {"do": "expect", "param": "coverage", "value": 0.8},
//    {"do": "save"}, {"do": "screenshot", "path": "out/storm.png"}, {"do": "quit"}]
//   A growing cloud (issue 26): {"do": "growth", "name": "storm_growth", "action": "pause"} (start, pause, resume,
//   step: one step while paused, reset), {"do": "expect_growth", "name": "storm_growth", "step": 3, "paused": true}
//   ("min_step": at least that step)
#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "editor/model/cloud_map_canvas.h"
#include "engine/core/json.h"

namespace cumulo::editor {

enum class ScriptOp {
  SelectState,  // name
  Set,          // param, value (the selected state)
  Paint,        // channel, uv (x, y), radius, value, strength: one dab, one stroke
  Undo,
  Redo,
  Save,
  Event,       // name: app::schedule_event
  Wait,        // frames
  Screenshot,  // path (as written in the script)
  Quit,
  CreateState,     // name, other = template ("from"; empty: defaults)
  DuplicateState,  // name, other = the copy's id ("as")
  RenameState,     // name, other = new id ("to")
  DeleteState,     // name
  Lightning,       // a flash at the camera's target
  TimeOfDay,       // hours
  ExpectDirty,     // flag: the document's dirty() must equal it
  Expect,          // param, value: the selected state's parameter must equal it
  MoveCloudscape,  // name (the entity's), position: a world edit, undoable with the document's
  ExpectCloudscape,  // name, position: the entity's position must equal it (within a millimetre)
  ExpectCamera,    // position: the viewer's camera must stand there (within a millimetre)
  Growth,          // name (the CloudGrowth entity's), other = start | pause | resume | step | reset (as its panel)
  ExpectGrowth,    // name, step, min_step and/or paused (-1: not checked): the growth's target step and pause
};

struct ScriptAction {
  ScriptOp op = ScriptOp::Quit;
  std::string where;  // "FILE: $[i]": prefix for errors raised when the action runs
  std::string name;
  std::string other;
  std::string param;
  Json value;  // set / expect: as written (checked against the parameter's kind and range)
  MapChannel channel = MapChannel::Coverage;
  glm::vec2 uv{0.0f};
  float radius = 0.0f, paint_value = 0.0f, strength = 1.0f;
  int frames = 0;       // wait: frames; -1: wait `seconds`, or until `path` exists (at most `seconds`)
  float seconds = 0.0f;  // wait: real time
  std::filesystem::path path;
  float hours = 0.0f;
  glm::vec3 position{0.0f};
  bool flag = false;  // expect_dirty: the value; save: expect_failure; quit: discard (unsaved changes)
  int step = -1;      // expect_growth: the target step (-1: not checked)
  int min_step = -1;  // expect_growth: the target step at least (-1: not checked)
  int paused = -1;    // expect_growth: 1 paused, 0 not (-1: not checked)
};

const char* script_op_name(ScriptOp op);  // the "do" string
std::vector<ScriptAction> load_editor_script(const std::filesystem::path& file);
std::vector<ScriptAction> parse_editor_script(const std::string& text, const std::string& name);

}  // namespace cumulo::editor
