#pragma once
// Systems in ordered phases (flecs-style: order by phase, then by insertion; no pairwise dependencies).
//
//   Scheduler sched;
//   sched.add_system(Phase::Update, "wind", [](World& w, const FrameContext& f) {
//     w.view<const Wind, Transform>().each([&](const Wind& wind, Transform& t) { t.position += wind.v * f.dt; });
//   });
//   for (int i = 0; i < steps; ++i) sched.step(world, 1.0 / 60.0);   // fixed simulation steps
//   sched.extract(world);                                             // once per rendered frame
//
// Deferred commands (world.defer()) are applied after every system, so the next system sees them.
// A system that throws is reported as "system 'NAME' (PHASE): message" in a cumulo::Error.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace cumulo::ecs {

class World;

enum class Phase : uint8_t { Input, PreUpdate, Update, PostUpdate, Extract };
inline constexpr int kPhaseCount = 5;
const char* phase_name(Phase phase);

struct FrameContext {
  double dt = 0.0;    // fixed simulation step, seconds
  double time = 0.0;  // simulated seconds before this step
  uint64_t step = 0;  // index of this step, from 0
};

class Scheduler {
 public:
  using SystemFn = std::function<void(World&, const FrameContext&)>;
  struct System {
    Phase phase;
    std::string name;
    std::shared_ptr<SystemFn> fn;  // shared so a running system survives its own removal
    bool enabled = true;
    double last_ms = 0.0;  // CPU time of its last run (for stats and the editor)
  };

  // Names must be unique (they identify systems in errors, stats and set_enabled).
  void add_system(Phase phase, std::string name, SystemFn fn);
  bool remove_system(std::string_view name);
  void set_enabled(std::string_view name, bool enabled);  // throws for an unknown name

  // One fixed simulation step: world.update_events(), then Input..PostUpdate. Returns the step's context.
  FrameContext step(World& world, double dt);
  // The Extract phase, with the context of the last step (a read-only snapshot for the renderer).
  void extract(World& world);
  // step() then extract().
  void tick(World& world, double dt);
  // Runs one phase's systems in insertion order (no event update).
  void run_phase(World& world, Phase phase, const FrameContext& ctx);

  const std::vector<System>& systems() const { return systems_; }  // in execution order
  double time() const { return time_; }
  uint64_t steps() const { return steps_; }
  const FrameContext& last_context() const { return last_; }

 private:
  std::vector<System> systems_;  // kept sorted by phase (stable, so insertion order within a phase)
  double time_ = 0.0;
  uint64_t steps_ = 0;
  FrameContext last_;
};

}  // namespace cumulo::ecs
