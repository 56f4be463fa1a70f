// `cumulo edit --script FILE`: the editor performs a JSON array of actions with no person at the keys,
// so CI tests the real editor under Xvfb. Actions run in order, as many per frame as come before a
// `wait` or a `screenshot` (which waits for its frame to be read back); a refused action stops the
// script with its file, index and reason, the window closes, and `cumulo edit` exits non-zero.
#include <algorithm>

#include "editor/editor.h"
#include "editor/model/weather_params.h"
#include "engine/app/game_events.h"
#include "engine/app/simulation.h"
#include "engine/core/error.h"
#include "engine/platform/window.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/scene/cloudscape.h"

namespace cumulo::editor {

void Editor::set_script(std::vector<ScriptAction> actions, std::filesystem::path file) {
  script_ = std::move(actions);
  script_file_ = std::move(file);
  script_pc_ = 0;
  script_error_.clear();
}

std::optional<std::filesystem::path> Editor::take_screenshot_request() {
  auto r = std::move(screenshot_request_);
  screenshot_request_.reset();
  return r;
}

void Editor::screenshot_written(const std::filesystem::path& path, const std::string& error) {
  script_waiting_screenshot_ = false;
  if (!error.empty()) {
    script_error_ = error;
    window_->window.request_close();
    quit_confirmed_ = true;
    return;
  }
  message(EditorMessage::Level::Info, "wrote screenshot " + path.string());
  std::printf("cumulo: wrote screenshot %s\n", path.string().c_str());
}

void Editor::run_script_step() {
  if (!script_error_.empty() || script_pc_ >= script_.size() || script_waiting_screenshot_) return;
  if (script_wait_ > 0) {
    --script_wait_;
    return;
  }
  if (script_wait_file_) {
    std::error_code ec;
    if (!std::filesystem::exists(*script_wait_file_, ec)) {
      if (time_s_ < script_resume_s_) return;
      script_error_ = strf("%s: waited %.0f s for %s, which never appeared", script_file_.string().c_str(),
                           script_wait_limit_s_, script_wait_file_->string().c_str());
      message(EditorMessage::Level::Error, script_error_);
      quit_confirmed_ = true;
      window_->window.request_close();
      return;
    }
    script_wait_file_.reset();
    script_resume_s_ = 0.0;  // the file came: the limit no longer holds the script
  } else if (time_s_ < script_resume_s_) {
    return;
  }
  while (script_pc_ < script_.size()) {
    const ScriptAction& a = script_[script_pc_++];
    try {
      execute(a);
    } catch (const Error& e) {
      script_error_ = a.where + " (" + script_op_name(a.op) + "): " + e.what();
      message(EditorMessage::Level::Error, script_error_);
      quit_confirmed_ = true;  // the script failed: nothing is saved, the run ends
      window_->window.request_close();
      return;
    }
    if (a.op == ScriptOp::Wait || a.op == ScriptOp::Screenshot || a.op == ScriptOp::Quit) break;
  }
}

void Editor::execute(const ScriptAction& a) {
  WeatherDocument& doc = *doc_;
  auto require_state = [&](const std::string& id) {
    if (!doc.has(id)) {
      std::string known;
      for (const std::string& k : doc.ids()) known += (known.empty() ? "" : ", ") + k;
      fail("no weather state \"%s\" (known: %s)", id.c_str(), known.c_str());
    }
  };
  switch (a.op) {
    case ScriptOp::SelectState:
      require_state(a.name);
      selected = a.name;
      pin_selected = true;
      update_preview();
      break;
    case ScriptOp::Set: {
      const std::string id = target_state();
      require_state(id);
      doc.set(id, a.param, a.value);
      sync_live();
      break;
    }
    case ScriptOp::Paint: {
      const std::string id = target_state();
      require_state(id);
      doc.begin_stroke(id);
      doc.paint(id, a.channel, a.uv, a.radius, a.paint_value, a.strength);
      doc.end_stroke();
      sync_live();
      break;
    }
    case ScriptOp::Undo:
      if (!undo()) fail("nothing to undo");
      break;
    case ScriptOp::Redo:
      if (!redo()) fail("nothing to redo");
      break;
    case ScriptOp::Save:
      if (a.flag) {  // "expect_failure": a test of a failed save (the document and the files stay as they were)
        try {
          doc.save();
        } catch (const Error& e) {
          message(EditorMessage::Level::Error, std::string("save failed, nothing was lost: ") + e.what());
          std::printf("cumulo: save failed as expected: %s\n", e.what());
          break;
        }
        fail("the save was expected to fail and did not");
      }
      doc.save();  // a failure stops the script with the document's message (file and OS reason)
      sync_live();
      message(EditorMessage::Level::Info, "saved " + doc.folder().string());
      break;
    case ScriptOp::Event:
      app::schedule_event(*world_, a.name, sim_time);
      break;
    case ScriptOp::Wait:
      if (a.frames >= 0) {
        script_wait_ = uint32_t(a.frames);
      } else {
        script_resume_s_ = time_s_ + a.seconds;
        script_wait_limit_s_ = a.seconds;
        if (!a.path.empty()) script_wait_file_ = a.path;
      }
      break;
    case ScriptOp::Screenshot:
      screenshot_request_ = a.path;
      script_waiting_screenshot_ = true;
      break;
    case ScriptOp::Quit:
      if (doc.dirty() && !a.flag) {
        std::string ids;
        for (const std::string& id : doc.dirty_ids()) ids += (ids.empty() ? "" : ", ") + id;
        fail("unsaved changes (%s): save first, or quit with \"discard\": true", ids.c_str());
      }
      quit_confirmed_ = true;
      window_->window.request_close();
      break;
    case ScriptOp::CreateState:
      doc.create(a.name, a.other);
      selected = a.name;
      sync_live();
      break;
    case ScriptOp::DuplicateState:
      doc.duplicate(a.name, a.other);
      sync_live();
      break;
    case ScriptOp::RenameState:
    case ScriptOp::DeleteState: {
      const auto used = states_in_use();
      if (std::find(used.begin(), used.end(), a.name) != used.end())
        fail("the level names \"%s\" (scheduler, zone or trigger): it cannot be renamed or deleted while it runs",
             a.name.c_str());
      if (a.op == ScriptOp::RenameState) doc.rename(a.name, a.other);
      else doc.remove(a.name);
      if (selected == a.name) selected = a.op == ScriptOp::RenameState ? a.other : std::string();
      sync_live();
      break;
    }
    case ScriptOp::Lightning:
      clouds::gameplay::strike_lightning(*world_, camera.position + camera.forward * target_distance);
      break;
    case ScriptOp::TimeOfDay: {
      scene::SunSource sun = scene::find_sun(*world_);
      if (!sun.time) fail("the level has no TimeOfDay");
      sun.time->hours = a.hours;
      break;
    }
    case ScriptOp::ExpectDirty:
      if (doc.dirty() != a.flag) fail("expected the document %s, it is %s", a.flag ? "dirty" : "clean", doc.dirty() ? "dirty" : "clean");
      break;
    case ScriptOp::ExpectCamera: {
      const auto* viewer = world_->try_resource<app::Viewer>();
      const auto* t = viewer ? static_cast<const ecs::World&>(*world_).try_get<scene::Transform>(viewer->entity) : nullptr;
      if (!t) fail("the run has no camera");
      if (glm::distance(t->position, a.position) > 1e-3f)
        fail("the camera is at (%g, %g, %g), expected (%g, %g, %g)", t->position.x, t->position.y, t->position.z,
             a.position.x, a.position.y, a.position.z);
      break;
    }
    case ScriptOp::Growth:
    case ScriptOp::ExpectGrowth: {
      clouds::gameplay::CloudGrowth* g = nullptr;
      std::string known;
      world_->view<clouds::gameplay::CloudGrowth>().each([&](ecs::Entity ent, clouds::gameplay::CloudGrowth& c) {
        const auto* n = static_cast<const ecs::World&>(*world_).try_get<ecs::Name>(ent);
        const std::string name = n ? n->value : std::string();
        known += (known.empty() ? "" : ", ") + name;
        if (name == a.name) g = &c;
      });
      if (!g) fail("no CloudGrowth entity \"%s\" (known: %s)", a.name.c_str(), known.empty() ? "none" : known.c_str());
      if (a.op == ScriptOp::ExpectGrowth) {
        if (a.step >= 0 && g->target_steps != a.step)
          fail("%s is at step %d, expected %d", a.name.c_str(), g->target_steps, a.step);
        if (a.min_step >= 0 && g->target_steps < a.min_step)
          fail("%s is at step %d, expected %d or more", a.name.c_str(), g->target_steps, a.min_step);
        if (a.paused >= 0 && g->paused != (a.paused == 1))
          fail("%s is %s, expected %s", a.name.c_str(), g->paused ? "paused" : "not paused",
               a.paused == 1 ? "paused" : "not paused");
        break;
      }
      // What the events panel's controls do (panels/events_panel.cpp).
      if (a.other == "start") {
        if (g->ended) fail("%s has ended: reset it first", a.name.c_str());
        g->running = true;
      } else if (a.other == "pause" || a.other == "resume") {
        g->paused = a.other == "pause";
      } else if (a.other == "step") {
        if (!clouds::gameplay::cloud_growth_can_step_once(*g))
          fail("%s steps one at a time only while running and paused (it is %s)", a.name.c_str(),
               clouds::gameplay::cloud_growth_state(*g));
        g->step_once = true;
      } else {
        clouds::gameplay::request_cloud_growth_reset(*world_, *g, sim_time);
      }
      break;
    }
    case ScriptOp::MoveCloudscape:
    case ScriptOp::ExpectCloudscape: {
      ecs::Entity found = ecs::Entity::null();
      std::string known;
      world_->view<const clouds::Cloudscape, const scene::Transform>().each(
          [&](ecs::Entity ent, const clouds::Cloudscape&, const scene::Transform&) {
            const auto* n = static_cast<const ecs::World&>(*world_).try_get<ecs::Name>(ent);
            const std::string name = n ? n->value : std::string();
            known += (known.empty() ? "" : ", ") + name;
            if (name == a.name) found = ent;
          });
      if (found.is_null()) fail("no Cloudscape entity \"%s\" (known: %s)", a.name.c_str(), known.c_str());
      scene::Transform& t = world_->get<scene::Transform>(found);
      if (a.op == ScriptOp::ExpectCloudscape) {
        if (glm::distance(t.position, a.position) > 1e-3f)
          fail("%s is at (%g, %g, %g), expected (%g, %g, %g)", a.name.c_str(), t.position.x, t.position.y, t.position.z,
               a.position.x, a.position.y, a.position.z);
        break;
      }
      auto put = [found](glm::vec3 p) {
        return [found, p](ecs::World& w) {
          if (auto* tr = w.try_get<scene::Transform>(found)) tr->position = p;
        };
      };
      push_world_edit("move " + a.name, put(t.position), put(a.position));
      t.position = a.position;
      break;
    }
    case ScriptOp::Expect: {
      const std::string id = target_state();
      require_state(id);
      const ParamInfo* p = find_param(a.param);
      Json have = get_param(doc.json(id), a.param);
      Json want = p ? normalize_param_value(*p, a.value) : a.value;
      const bool equal = have.is_number() && want.is_number() ? std::abs(have.get<double>() - want.get<double>()) < 1e-6
                                                              : have == want;
      if (!equal) fail("%s of %s: expected %s, is %s", a.param.c_str(), id.c_str(), want.dump().c_str(), have.dump().c_str());
      break;
    }
  }
}

}  // namespace cumulo::editor
