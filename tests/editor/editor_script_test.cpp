#include "editor/model/editor_script.h"

#include <gtest/gtest.h>

#include "engine/core/file_io.h"
#include "tests/support/temp_dir.h"

namespace cumulo::editor {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_editor_script(text, "s.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(EditorScript, ParsesEveryAction) {
  cumulo::test::TempDir tmp(cumulo::test::test_temp_name("cumulo_editor_script"));
  const std::string text = R"([
    {"do": "select_state", "name": "storm"},
    {"do": "set", "param": "wind.direction", "value": [0, 0, 1]},
    {"do": "paint", "channel": "precipitation", "x": 0.25, "y": 1, "radius": 0.1, "value": 0.5, "strength": 0.3},
    {"do": "paint", "channel": "coverage", "x": 0, "y": 0, "radius": 1, "value": 0},
    {"do": "undo"}, {"do": "redo"}, {"do": "save"},
    {"do": "event", "name": "stormbird_killed"},
    {"do": "wait", "frames": 30},
    {"do": "screenshot", "path": "out/a.png"},
    {"do": "create_state", "name": "calm"},
    {"do": "create_state", "name": "calm2", "from": "clear"},
    {"do": "duplicate_state", "name": "storm", "as": "storm_b"},
    {"do": "rename_state", "name": "storm_b", "to": "storm_c"},
    {"do": "delete_state", "name": "storm_c"},
    {"do": "lightning"},
    {"do": "time_of_day", "hours": 18.5},
    {"do": "expect_dirty", "value": true},
    {"do": "expect", "param": "description", "value": "x"},
    {"do": "quit"},
    {"do": "save", "expect_failure": true},
    {"do": "quit", "discard": true},
    {"do": "move_cloudscape", "name": "cloudscape", "position": [1, 2, 3]},
    {"do": "expect_cloudscape", "name": "cloudscape", "position": [1, 2, 3]}
  ])";
  write_file_atomic(tmp.path / "s.json", text);
  const std::vector<ScriptAction> a = load_editor_script(tmp.path / "s.json");
  ASSERT_EQ(a.size(), 24u);
  EXPECT_EQ(a[0].op, ScriptOp::SelectState);
  EXPECT_EQ(a[0].name, "storm");
  EXPECT_EQ(a[1].op, ScriptOp::Set);
  EXPECT_EQ(a[1].param, "wind.direction");
  EXPECT_EQ(a[1].value, Json::array({0, 0, 1}));
  EXPECT_EQ(a[1].where, (tmp.path / "s.json").string() + ": $[1]");
  EXPECT_EQ(a[2].op, ScriptOp::Paint);
  EXPECT_EQ(a[2].channel, MapChannel::Precipitation);
  EXPECT_EQ(a[2].uv, glm::vec2(0.25f, 1.0f));
  EXPECT_FLOAT_EQ(a[2].radius, 0.1f);
  EXPECT_FLOAT_EQ(a[2].paint_value, 0.5f);
  EXPECT_FLOAT_EQ(a[2].strength, 0.3f);
  EXPECT_FLOAT_EQ(a[3].strength, 1.0f);
  EXPECT_EQ(a[4].op, ScriptOp::Undo);
  EXPECT_EQ(a[5].op, ScriptOp::Redo);
  EXPECT_EQ(a[6].op, ScriptOp::Save);
  EXPECT_EQ(a[7].op, ScriptOp::Event);
  EXPECT_EQ(a[7].name, "stormbird_killed");
  EXPECT_EQ(a[8].frames, 30);
  EXPECT_EQ(a[9].path, "out/a.png");
  EXPECT_EQ(a[10].other, "");
  EXPECT_EQ(a[11].other, "clear");
  EXPECT_EQ(a[12].op, ScriptOp::DuplicateState);
  EXPECT_EQ(a[12].other, "storm_b");
  EXPECT_EQ(a[13].op, ScriptOp::RenameState);
  EXPECT_EQ(a[13].other, "storm_c");
  EXPECT_EQ(a[14].op, ScriptOp::DeleteState);
  EXPECT_EQ(a[15].op, ScriptOp::Lightning);
  EXPECT_FLOAT_EQ(a[16].hours, 18.5f);
  EXPECT_TRUE(a[17].flag);
  EXPECT_EQ(a[18].op, ScriptOp::Expect);
  EXPECT_EQ(a[18].value, "x");
  EXPECT_EQ(a[19].op, ScriptOp::Quit);
  EXPECT_FALSE(a[19].flag);
  EXPECT_FALSE(a[6].flag);
  EXPECT_TRUE(a[20].flag) << "save expect_failure";
  EXPECT_TRUE(a[21].flag) << "quit discard";
  EXPECT_EQ(a[22].op, ScriptOp::MoveCloudscape);
  EXPECT_EQ(a[22].name, "cloudscape");
  EXPECT_EQ(a[22].position, glm::vec3(1, 2, 3));
  EXPECT_EQ(a[23].op, ScriptOp::ExpectCloudscape);
  for (const ScriptAction& x : a) EXPECT_NE(std::string(script_op_name(x.op)), "?");
  EXPECT_TRUE(parse_editor_script("[]", "e.json").empty());
  const std::vector<ScriptAction> w = parse_editor_script(R"([{"do": "wait", "seconds": 2.5}])", "w.json");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].frames, -1);
  EXPECT_FLOAT_EQ(w[0].seconds, 2.5f);
  const std::vector<ScriptAction> f = parse_editor_script(R"([{"do": "wait", "file": "done", "seconds": 30},
                                                              {"do": "expect_camera", "position": [1, 2, 3]}])", "f.json");
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[0].path, "done");
  EXPECT_FLOAT_EQ(f[0].seconds, 30.0f);
  EXPECT_EQ(f[1].op, ScriptOp::ExpectCamera);
  EXPECT_EQ(f[1].position, glm::vec3(1, 2, 3));
  const std::vector<ScriptAction> g = parse_editor_script(R"([{"do": "growth", "name": "storm_growth", "action": "step"},
      {"do": "expect_growth", "name": "storm_growth", "step": 3, "paused": true},
      {"do": "expect_growth", "name": "storm_growth", "min_step": 2}])", "g.json");
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].op, ScriptOp::Growth);
  EXPECT_EQ(g[0].name, "storm_growth");
  EXPECT_EQ(g[0].other, "step");
  EXPECT_EQ(g[1].op, ScriptOp::ExpectGrowth);
  EXPECT_EQ(g[1].step, 3);
  EXPECT_EQ(g[1].min_step, -1);
  EXPECT_EQ(g[1].paused, 1);
  EXPECT_EQ(g[2].step, -1);
  EXPECT_EQ(g[2].min_step, 2);
  EXPECT_EQ(g[2].paused, -1);
}

TEST(EditorScript, RefusesWithTheFileAndThePlace) {
  std::string e = error_of(R"([{"do": "quit"}, {"do": "fly"}])");
  EXPECT_EQ(e.rfind("s.json: $[1].do: unknown action \"fly\" (known: select_state, set, paint,", 0), 0u) << e;
  EXPECT_NE(e.find("expect_dirty, expect, move_cloudscape, expect_cloudscape, expect_camera, growth, expect_growth)"),
            std::string::npos)
      << e;
  e = error_of(R"([{"do": "growth", "name": "storm_growth", "action": "rewind"}])");
  EXPECT_NE(e.find("s.json: $[0].action: unknown growth action \"rewind\" (known: start, pause, resume, step, reset)"),
            std::string::npos)
      << e;
  e = error_of(R"([{"do": "expect_growth", "name": "storm_growth"}])");
  EXPECT_NE(e.find("s.json: $[0]: \"expect_growth\" needs \"step\", \"min_step\" or \"paused\""), std::string::npos) << e;
  e = error_of(R"([{"do": "expect_growth", "name": "storm_growth", "min_step": -2}])");
  EXPECT_NE(e.find("s.json: $[0].min_step: expected a step >= 0"), std::string::npos) << e;
  e = error_of(R"([{"do": "undo", "steps": 2}])");
  EXPECT_NE(e.find("s.json: $[0]: unknown key \"steps\" for \"undo\""), std::string::npos) << e;
  e = error_of(R"([{"do": "paint", "channel": "coverage", "x": 0.5, "radius": 0.1, "value": 0}])");
  EXPECT_NE(e.find("s.json: $[0]: \"paint\" needs \"y\""), std::string::npos) << e;
  e = error_of(R"([{"do": "wait"}])");
  EXPECT_NE(e.find("s.json: $[0]: expected \"frames\" or \"seconds\""), std::string::npos) << e;
  e = error_of(R"([{"do": "wait", "frames": 2, "seconds": 1}])");
  EXPECT_NE(e.find("(one of them)"), std::string::npos) << e;
  e = error_of(R"([{"do": "wait", "frames": "ten"}])");
  EXPECT_NE(e.find("s.json: $[0].frames: expected"), std::string::npos) << e;
  e = error_of(R"([{"do": "paint", "channel": "coverage", "x": 1.5, "y": 0, "radius": 0.1, "value": 0}])");
  EXPECT_NE(e.find("s.json: $[0].x: value 1.5 out of range [0, 1]"), std::string::npos) << e;
  e = error_of(R"([{"do": "paint", "channel": "coverage", "x": 0, "y": 0, "radius": 0, "value": 0}])");
  EXPECT_NE(e.find("$[0].radius: expected a radius in (0, 1]"), std::string::npos) << e;
  e = error_of(R"([{"do": "paint", "channel": "alpha", "x": 0, "y": 0, "radius": 0.1, "value": 0}])");
  EXPECT_NE(e.find("$[0].channel: expected \"coverage\""), std::string::npos) << e;
  e = error_of(R"([{"do": "set", "param": "colour", "value": 1}])");
  EXPECT_NE(e.find("$[0].param: unknown parameter \"colour\" (known: coverage,"), std::string::npos) << e;
  e = error_of(R"([{"do": "set", "param": "coverage", "value": 1.5}])");
  EXPECT_NE(e.find("$[0].value: 1.5 is out of range [0, 1] for coverage"), std::string::npos) << e;
  e = error_of(R"([{"do": "expect", "param": "wind.direction", "value": 3}])");
  EXPECT_NE(e.find("$[0].value: expected an array of 3 numbers"), std::string::npos) << e;
  e = error_of(R"([{"do": "select_state", "name": "../etc"}])");
  EXPECT_NE(e.find("$[0].name: \"../etc\" is not a state id"), std::string::npos) << e;
  e = error_of(R"([{"do": "time_of_day", "hours": 25}])");
  EXPECT_NE(e.find("$[0].hours: value 25 out of range [0, 24]"), std::string::npos) << e;
  e = error_of(R"([{"do": "expect_dirty", "value": 1}])");
  EXPECT_NE(e.find("$[0].value: expected a boolean"), std::string::npos) << e;
  e = error_of(R"([{"name": "x"}])");
  EXPECT_NE(e.find("$[0]: missing \"do\""), std::string::npos) << e;
  e = error_of(R"([3])");
  EXPECT_NE(e.find("$[0]: expected an action object"), std::string::npos) << e;
  e = error_of(R"({"do": "quit"})");
  EXPECT_NE(e.find("s.json: $: expected an array of actions"), std::string::npos) << e;
  e = error_of(R"([{"do": "quit"},])");
  EXPECT_NE(e.find("s.json:1:"), std::string::npos) << e;  // syntax errors name line and column
  EXPECT_THROW(load_editor_script("/nonexistent/s.json"), Error);
}

}  // namespace
}  // namespace cumulo::editor
