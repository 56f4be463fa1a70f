#include "editor/model/editor_script.h"

#include <algorithm>

#include <set>

#include "editor/model/weather_document.h"
#include "editor/model/weather_params.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace cumulo::editor {
namespace {

struct OpSpec {
  ScriptOp op;
  const char* name;
  std::vector<std::string> required, optional;
};

const std::vector<OpSpec>& op_specs() {
  using O = ScriptOp;
  static const std::vector<OpSpec> specs = {
      {O::SelectState, "select_state", {"name"}, {}},
      {O::Set, "set", {"param", "value"}, {}},
      {O::Paint, "paint", {"channel", "x", "y", "radius", "value"}, {"strength"}},
      {O::Undo, "undo", {}, {}},
      {O::Redo, "redo", {}, {}},
      {O::Save, "save", {}, {"expect_failure"}},
      {O::Event, "event", {"name"}, {}},
      {O::Wait, "wait", {}, {"frames", "seconds", "file"}},
      {O::Screenshot, "screenshot", {"path"}, {}},
      {O::Quit, "quit", {}, {"discard"}},
      {O::CreateState, "create_state", {"name"}, {"from"}},
      {O::DuplicateState, "duplicate_state", {"name", "as"}, {}},
      {O::RenameState, "rename_state", {"name", "to"}, {}},
      {O::DeleteState, "delete_state", {"name"}, {}},
      {O::Lightning, "lightning", {}, {}},
      {O::TimeOfDay, "time_of_day", {"hours"}, {}},
      {O::ExpectDirty, "expect_dirty", {"value"}, {}},
      {O::Expect, "expect", {"param", "value"}, {}},
      {O::MoveCloudscape, "move_cloudscape", {"name", "position"}, {}},
      {O::ExpectCloudscape, "expect_cloudscape", {"name", "position"}, {}},
      {O::ExpectCamera, "expect_camera", {"position"}, {}},
      {O::Growth, "growth", {"name", "action"}, {}},
      {O::ExpectGrowth, "expect_growth", {"name"}, {"step", "min_step", "paused"}},
  };
  return specs;
}

std::string known_ops() {
  std::string s;
  for (const OpSpec& o : op_specs()) s += (s.empty() ? "" : ", ") + std::string(o.name);
  return s;
}

void check_keys(const JsonView& v, const OpSpec& spec) {
  std::set<std::string> allowed = {"do"};
  allowed.insert(spec.required.begin(), spec.required.end());
  allowed.insert(spec.optional.begin(), spec.optional.end());
  for (const std::string& k : v.keys())
    if (!allowed.count(k)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      v.fail("unknown key \"" + k + "\" for \"" + spec.name + "\" (expected: " + list + ")");
    }
  for (const std::string& k : spec.required)
    if (!v.has(k)) v.fail(std::string("\"") + spec.name + "\" needs \"" + k + "\"");
}

std::string state_id(const JsonView& v) {
  const std::string id = v.as<std::string>();
  if (!valid_state_id(id)) v.fail("\"" + id + "\" is not a state id (letters, digits, '_' and '-')");
  return id;
}

const ParamInfo& param(const JsonView& v) {
  const std::string path = v.as<std::string>();
  if (const ParamInfo* p = find_param(path)) return *p;
  std::string known;
  for (const ParamInfo& p : weather_params()) known += (known.empty() ? "" : ", ") + p.path;
  v.fail("unknown parameter \"" + path + "\" (known: " + known + ")");
}

// An expect_growth step: -1 when absent (not checked).
int growth_step(const JsonView& v, const char* key) {
  if (!v.has(key)) return -1;
  const int n = v[key].as<int>();
  if (n < 0) v[key].fail("expected a step >= 0");
  return n;
}

ScriptAction parse_action(const JsonView& v) {
  if (!v.is_object()) v.fail("expected an action object {\"do\": ...}");
  if (!v.has("do")) v.fail("missing \"do\" (one of: " + known_ops() + ")");
  const std::string op = v["do"].as<std::string>();
  const OpSpec* spec = nullptr;
  for (const OpSpec& o : op_specs())
    if (op == o.name) spec = &o;
  if (!spec) v["do"].fail("unknown action \"" + op + "\" (known: " + known_ops() + ")");
  check_keys(v, *spec);
  ScriptAction a;
  a.op = spec->op;
  a.where = v.where();
  switch (a.op) {
    case ScriptOp::SelectState:
    case ScriptOp::DeleteState:
      a.name = state_id(v["name"]);
      break;
    case ScriptOp::CreateState:
      a.name = state_id(v["name"]);
      if (v.has("from")) a.other = state_id(v["from"]);
      break;
    case ScriptOp::DuplicateState:
      a.name = state_id(v["name"]);
      a.other = state_id(v["as"]);
      break;
    case ScriptOp::RenameState:
      a.name = state_id(v["name"]);
      a.other = state_id(v["to"]);
      break;
    case ScriptOp::Event:
      a.name = v["name"].as<std::string>();
      if (a.name.empty()) v["name"].fail("expected an event name");
      break;
    case ScriptOp::ExpectCamera:
      a.position = v["position"].as_vec3();
      break;
    case ScriptOp::MoveCloudscape:
    case ScriptOp::ExpectCloudscape:
      a.name = v["name"].as<std::string>();
      a.position = v["position"].as_vec3();
      break;
    case ScriptOp::Set:
    case ScriptOp::Expect: {
      const ParamInfo& p = param(v["param"]);
      a.param = p.path;
      a.value = v["value"].raw();
      if (auto why = check_param_value(p, a.value)) v["value"].fail(*why + " for " + p.path);
      break;
    }
    case ScriptOp::Paint: {
      const auto channel = parse_map_channel(v["channel"].as<std::string>());
      if (!channel) v["channel"].fail("expected \"coverage\", \"precipitation\" or \"type\"");
      a.channel = *channel;
      a.uv = {v["x"].as_float_in(0.0f, 1.0f), v["y"].as_float_in(0.0f, 1.0f)};
      a.radius = v["radius"].as<float>();
      if (!(a.radius > 0.0f && a.radius <= 1.0f)) v["radius"].fail("expected a radius in (0, 1]");
      a.paint_value = v["value"].as_float_in(0.0f, 1.0f);
      if (v.has("strength")) a.strength = v["strength"].as_float_in(0.0f, 1.0f);
      break;
    }
    case ScriptOp::Wait:
      // Frames (rendered), or seconds of real time (a person, or another program, acting meanwhile).
      if (v.has("file")) {  // until another program creates the file, at most `seconds` (default 600)
        if (v.has("frames")) v.fail("expected \"file\" with \"seconds\" (the longest wait), not \"frames\"");
        const std::string f = v["file"].as<std::string>();
        if (f.empty()) v["file"].fail("expected a file path");
        a.path = f;
        a.seconds = v.has("seconds") ? v["seconds"].as_float_in(0.0f, 3600.0f) : 600.0f;
        a.frames = -1;
        break;
      }
      if (v.has("frames") == v.has("seconds")) v.fail("expected \"frames\" or \"seconds\" (one of them)");
      if (v.has("frames")) {
        a.frames = v["frames"].as<int>();
        if (a.frames < 0) v["frames"].fail("expected a number of frames >= 0");
      } else {
        a.seconds = v["seconds"].as_float_in(0.0f, 3600.0f);
        a.frames = -1;
      }
      break;
    case ScriptOp::Screenshot: {
      const std::string p = v["path"].as<std::string>();
      if (p.empty()) v["path"].fail("expected a file path");
      a.path = p;
      break;
    }
    case ScriptOp::TimeOfDay:
      a.hours = v["hours"].as_float_in(0.0f, 24.0f);
      break;
    case ScriptOp::ExpectDirty:
      a.flag = v["value"].as<bool>();
      break;
    case ScriptOp::Save:
      a.flag = v.get<bool>("expect_failure", false);
      break;
    case ScriptOp::Quit:
      a.flag = v.get<bool>("discard", false);
      break;
    case ScriptOp::Growth: {
      a.name = v["name"].as<std::string>();
      a.other = v["action"].as<std::string>();
      static const char* kActions[] = {"start", "pause", "resume", "step", "reset"};
      if (std::find(std::begin(kActions), std::end(kActions), a.other) == std::end(kActions))
        v["action"].fail("unknown growth action \"" + a.other + "\" (known: start, pause, resume, step, reset)");
      break;
    }
    case ScriptOp::ExpectGrowth:
      a.name = v["name"].as<std::string>();
      if (!v.has("step") && !v.has("min_step") && !v.has("paused"))
        v.fail("\"expect_growth\" needs \"step\", \"min_step\" or \"paused\"");
      a.step = growth_step(v, "step");
      a.min_step = growth_step(v, "min_step");
      if (v.has("paused")) a.paused = v["paused"].as<bool>() ? 1 : 0;
      break;
    case ScriptOp::Undo:
    case ScriptOp::Redo:
    case ScriptOp::Lightning:
      break;
  }
  return a;
}

}  // namespace

const char* script_op_name(ScriptOp op) {
  for (const OpSpec& o : op_specs())
    if (o.op == op) return o.name;
  return "?";
}

std::vector<ScriptAction> parse_editor_script(const std::string& text, const std::string& name) {
  const JsonDocument doc = parse_json_text(text, name);
  const JsonView root = doc.view();
  if (!root.is_array()) root.fail("expected an array of actions");
  std::vector<ScriptAction> out;
  for (const JsonView& v : root.elements()) out.push_back(parse_action(v));
  return out;
}

std::vector<ScriptAction> load_editor_script(const std::filesystem::path& file) {
  return parse_editor_script(read_file_text(file), file.string());
}

}  // namespace cumulo::editor
