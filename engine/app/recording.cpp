#include "engine/app/recording.h"

#include <algorithm>
#include <cmath>

#include "engine/app/game_events.h"
#include "engine/app/simulation.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/scene/components.h"

namespace cumulo::app {
namespace {

constexpr const char* kFormat = "cumulo-recording";

// World resources of a run being recorded or replayed.
struct RecordingState {
  Recording recording;
  bool has_pose = false;
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};
struct ReplayState {
  Recording recording;
  size_t next_pose = 0, next_event = 0;
};

scene::Transform* viewer_transform(ecs::World& w) {
  const auto* viewer = w.try_resource<Viewer>();
  if (!viewer || !w.valid(viewer->entity)) return nullptr;
  return w.has<scene::Transform>(viewer->entity) ? &w.get<scene::Transform>(viewer->entity) : nullptr;
}

template <typename T>
void check_ascending(const JsonView& list, const std::vector<T>& items) {
  for (size_t i = 1; i < items.size(); ++i)
    if (items[i].step < items[i - 1].step) list.at(i)["step"].fail("steps must not decrease along the list");
}

}  // namespace

Json recording_to_json(const Recording& r) {
  Json path = Json::array(), events = Json::array();
  for (const CameraSample& c : r.camera_path)
    path.push_back({{"step", c.step},
                    {"position", {c.position.x, c.position.y, c.position.z}},
                    {"rotation", {c.rotation.w, c.rotation.x, c.rotation.y, c.rotation.z}}});
  for (const RecordedEvent& e : r.events) events.push_back({{"step", e.step}, {"name", e.name}});
  Json j = {{"format", kFormat}, {"version", 1}, {"level", r.level}, {"seed", r.seed}, {"sim_hz", r.sim_hz}};
  if (r.time_of_day) j["time_of_day"] = *r.time_of_day;
  j["camera"] = r.camera;
  j["steps"] = r.steps;
  j["camera_path"] = std::move(path);
  j["events"] = std::move(events);
  return j;
}

Recording recording_from_json(const JsonView& v) {
  if (!v.is_object()) v.fail("expected an object (a cumulo recording)");
  for (const std::string& k : v.keys())
    if (k != "format" && k != "version" && k != "level" && k != "seed" && k != "sim_hz" && k != "time_of_day" &&
        k != "camera" && k != "steps" && k != "camera_path" && k != "events")
      v.fail("unknown key \"" + k + "\" (expected format, version, level, seed, sim_hz, time_of_day, camera, steps, "
             "camera_path, events)");
  if (v.get<std::string>("format") != kFormat) v["format"].fail(std::string("expected \"") + kFormat + "\"");
  if (v.get<int>("version") != 1) v["version"].fail("expected 1 (the only version)");
  Recording r;
  r.level = v.get<std::string>("level");
  r.seed = v.get<uint64_t>("seed");
  r.sim_hz = v.get<uint32_t>("sim_hz");
  if (r.sim_hz < 1 || r.sim_hz > 1000) v["sim_hz"].fail("expected 1..1000");
  if (v.has("time_of_day")) r.time_of_day = v["time_of_day"].as_float_in(0.0f, 24.0f);
  r.camera = v.get<std::string>("camera", "");
  r.steps = v.get<uint64_t>("steps");
  const JsonView path = v["camera_path"];
  for (const JsonView& c : path.elements()) {
    for (const std::string& k : c.keys())
      if (k != "step" && k != "position" && k != "rotation") c.fail("unknown key \"" + k + "\" (expected step, position, rotation)");
    CameraSample s;
    s.step = c.get<uint64_t>("step");
    s.position = c["position"].as_vec3();
    const glm::vec4 q = c["rotation"].as_vec4();
    if (!(glm::length(q) > 1e-6f)) c["rotation"].fail("expected a unit quaternion [w, x, y, z]");
    s.rotation = glm::normalize(glm::quat(q.x, q.y, q.z, q.w));
    r.camera_path.push_back(s);
  }
  check_ascending(path, r.camera_path);
  const JsonView events = v["events"];
  for (const JsonView& e : events.elements()) {
    for (const std::string& k : e.keys())
      if (k != "step" && k != "name") e.fail("unknown key \"" + k + "\" (expected step, name)");
    RecordedEvent ev;
    ev.step = e.get<uint64_t>("step");
    ev.name = e.get<std::string>("name");
    if (ev.name.empty()) e["name"].fail("expected an event name");
    r.events.push_back(std::move(ev));
  }
  check_ascending(events, r.events);
  for (const CameraSample& c : r.camera_path)
    if (c.step > r.steps) path.fail("a pose at step " + std::to_string(c.step) + ", after the recording's " +
                                    std::to_string(r.steps) + " steps");
  return r;
}

Recording load_recording(const std::filesystem::path& path) {
  const JsonDocument doc = load_json_file(path);
  return recording_from_json(doc.view());
}

void save_recording(const std::filesystem::path& path, const Recording& r) {
  write_file_atomic(path, recording_to_json(r).dump(1) + "\n");
}

void start_recording(Simulation& sim, const Recording& header) {
  RecordingState& s = sim.world().set_resource<RecordingState>();
  s.recording = header;
  s.recording.camera_path.clear();
  s.recording.events.clear();
}

Recording finish_recording(const Simulation& sim) {
  const auto* s = sim.world().try_resource<RecordingState>();
  if (!s) fail("finish_recording: the simulation is not being recorded (start_recording first)");
  Recording r = s->recording;
  r.steps = sim.steps();
  // Scheduled events (--event, schedule_event) that fired, in step order; a replay's events fire through
  // the replay and were logged by it.
  if (const auto* list = sim.world().try_resource<ScheduledEvents>())
    for (const ScheduledEvent& e : list->events)
      if (e.fired) r.events.push_back({e.step, e.name});
  std::stable_sort(r.events.begin(), r.events.end(), [](const RecordedEvent& a, const RecordedEvent& b) { return a.step < b.step; });
  return r;
}

void start_replay(Simulation& sim, const Recording& r) {
  if (uint32_t(std::lround(1.0 / sim.step_seconds())) != r.sim_hz)
    fail("replay: the recording steps at %u Hz, this run at %.0f Hz (give --sim-hz %u)", r.sim_hz, 1.0 / sim.step_seconds(),
         r.sim_hz);
  ReplayState& s = sim.world().set_resource<ReplayState>();
  s.recording = r;
  // Skip what lies before the simulation's next step (a replay attached after a fast-forward).
  const uint64_t now = sim.steps();
  while (s.next_event < r.events.size() && r.events[s.next_event].step < now) ++s.next_event;
}

bool replaying(const ecs::World& world) { return world.try_resource<ReplayState>() != nullptr; }

void add_record_replay_systems(ecs::Scheduler& sched) {
  // Replay first: the step then runs with the recorded pose and events, exactly as when recorded.
  sched.add_system(ecs::Phase::Input, "replay", [](ecs::World& w, const ecs::FrameContext& f) {
    auto* s = w.try_resource<ReplayState>();
    if (!s) return;
    const std::vector<CameraSample>& path = s->recording.camera_path;
    while (s->next_pose + 1 < path.size() && path[s->next_pose + 1].step <= f.step) ++s->next_pose;
    if (!path.empty() && path[s->next_pose].step <= f.step)
      if (scene::Transform* t = viewer_transform(w)) t->position = path[s->next_pose].position, t->rotation = path[s->next_pose].rotation;
    const std::vector<RecordedEvent>& events = s->recording.events;
    for (; s->next_event < events.size() && events[s->next_event].step <= f.step; ++s->next_event) {
      fire_event(w, events[s->next_event].name);
      if (auto* rec = w.try_resource<RecordingState>()) rec->recording.events.push_back({f.step, events[s->next_event].name});
    }
  });
  sched.add_system(ecs::Phase::Input, "record", [](ecs::World& w, const ecs::FrameContext& f) {
    auto* s = w.try_resource<RecordingState>();
    if (!s) return;
    const scene::Transform* t = viewer_transform(w);
    if (!t) return;
    if (s->has_pose && t->position == s->position && t->rotation == s->rotation) return;
    s->has_pose = true;
    s->position = t->position, s->rotation = t->rotation;
    s->recording.camera_path.push_back({f.step, t->position, t->rotation});
  });
}

}  // namespace cumulo::app
