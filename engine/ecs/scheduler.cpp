#include "engine/ecs/scheduler.h"

#include <algorithm>
#include <exception>

#include "engine/core/error.h"
#include "engine/core/time.h"
#include "engine/ecs/world.h"

namespace cumulo::ecs {

const char* phase_name(Phase phase) {
  switch (phase) {
    case Phase::Input:
      return "Input";
    case Phase::PreUpdate:
      return "PreUpdate";
    case Phase::Update:
      return "Update";
    case Phase::PostUpdate:
      return "PostUpdate";
    case Phase::Extract:
      return "Extract";
  }
  return "?";
}

void Scheduler::add_system(Phase phase, std::string name, SystemFn fn) {
  if (name.empty()) fail("ecs: add_system: empty system name");
  if (!fn) fail("ecs: add_system \"%s\": empty function", name.c_str());
  for (const System& s : systems_)
    if (s.name == name) fail("ecs: add_system: a system named \"%s\" already exists", name.c_str());
  // Insert after the last system of the same or an earlier phase.
  auto at = std::upper_bound(systems_.begin(), systems_.end(), phase,
                             [](Phase p, const System& s) { return uint8_t(p) < uint8_t(s.phase); });
  systems_.insert(at, System{phase, std::move(name), std::make_shared<SystemFn>(std::move(fn))});
}

bool Scheduler::remove_system(std::string_view name) {
  auto it = std::find_if(systems_.begin(), systems_.end(), [&](const System& s) { return s.name == name; });
  if (it == systems_.end()) return false;
  systems_.erase(it);
  return true;
}

void Scheduler::set_enabled(std::string_view name, bool enabled) {
  for (System& s : systems_)
    if (s.name == name) {
      s.enabled = enabled;
      return;
    }
  fail("ecs: set_enabled: no system named \"%.*s\"", int(name.size()), name.data());
}

void Scheduler::run_phase(World& world, Phase phase, const FrameContext& ctx) {
  // Index loop: a system may add or remove systems (e.g. a level switch); later ones see the change.
  for (size_t i = 0; i < systems_.size(); ++i) {
    if (systems_[i].phase != phase || !systems_[i].enabled) continue;
    Stopwatch sw;
    std::shared_ptr<SystemFn> fn = systems_[i].fn;  // keeps it alive if it removes itself
    const std::string name = systems_[i].name;
    try {
      (*fn)(world, ctx);
      world.flush();
    } catch (const std::exception& e) {
      throw Error(strf("system '%s' (%s): %s", name.c_str(), phase_name(phase), e.what()));
    }
    if (i < systems_.size() && systems_[i].fn == fn) systems_[i].last_ms = sw.ms();
  }
}

FrameContext Scheduler::step(World& world, double dt) {
  FrameContext ctx{dt, time_, steps_};
  last_ = ctx;
  world.update_events();
  for (Phase p : {Phase::Input, Phase::PreUpdate, Phase::Update, Phase::PostUpdate}) run_phase(world, p, ctx);
  ++steps_;
  time_ += dt;
  return ctx;
}

void Scheduler::extract(World& world) { run_phase(world, Phase::Extract, last_); }

void Scheduler::tick(World& world, double dt) {
  step(world, dt);
  extract(world);
}

}  // namespace cumulo::ecs
