#include "modules/clouds/soak/soak_command.h"

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "engine/app/game_events.h"
#include "engine/app/headless_session.h"
#include "engine/app/run_options.h"
#include "engine/app/sim_resources.h"
#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/gpu/live_objects.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/non_finite_probe.h"
#include "engine/scene/camera.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/soak/soak_path.h"
#include "modules/clouds/weather/level_weather.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds {
namespace {

struct SoakOptions {
  std::string level = "content/levels/sample/level.json";
  uint32_t frames = 10000, lap = 1000, width = 160, height = 90;
  std::string out;
  bool strict_timing = false;
  bool trace_heap = false;
  std::vector<int> modes = {30, 40, 60};  // the budget modes a lap switches between
  bool debug_views = true, weather = true, gameplay = true, day = true, fly = true;
};

constexpr uint32_t kLightningEvery = 60;  // frames: about 1.5 s of play

// What happens at each frame of a lap: the same every lap, so laps compare.
struct LapPlan {
  uint32_t lap = 1000;
  size_t states = 0;  // weather states forced in turn, one per lap / states frames
  std::vector<int> modes;
  bool debug_views = true, day = true;

  // The modes in turn, each twice a lap.
  int mode(uint32_t k) const { return modes[(uint64_t(k) * 2 * modes.size() / lap) % modes.size()]; }
  render::CloudDebugView debug(uint32_t k) const {
    if (!debug_views) return render::CloudDebugView::None;
    const uint32_t from = lap * 84 / 100, each = std::max(1u, lap * 3 / 100);
    if (k < from || k >= from + 4 * each) return render::CloudDebugView::None;
    constexpr render::CloudDebugView views[] = {render::CloudDebugView::Profile, render::CloudDebugView::Steps,
                                                render::CloudDebugView::LightGrid, render::CloudDebugView::Split};
    return views[(k - from) / each];
  }
  // The time of day at frame k: a day each lap, through the night, in eight held steps of 3 h (each a rebuild of what
  // the sun lights) and a sweep at dusk (the sun moving every frame, 15 degrees over 4 % of the lap).
  float hours(uint32_t k, float start) const {
    if (!day) return start;
    const double u = double(k) / lap;
    const double sweep_from = 0.70, sweep_to = 0.74;
    if (u >= sweep_from && u < sweep_to) return float(17.5 + (u - sweep_from) / (sweep_to - sweep_from));
    return float(3 * std::min(7, int(u * 8)));
  }
  // The weather state forced at frame k (index into the library's ids), or -1: one every lap / states frames.
  int forced_state(uint32_t k) const {
    for (size_t i = 0; i < states; ++i)
      if (i > 0 && k == uint32_t((uint64_t(i) * lap) / states)) return int(i);  // the first: the lap's restart
    return -1;
  }
  double seconds() const {  // of play: 1 / mode each frame
    double s = 0;
    for (uint32_t k = 0; k < lap; ++k) s += 1.0 / mode(k);
    return s;
  }
};

uint64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

// Resident memory by kind (/proc/self/status): anonymous (the heap, a driver's device memory, a JIT's output), file
// backed (shared libraries' code and data, paged in the first time a path runs: bounded by the files, never a leak)
// and shared memory.
struct ResidentKinds {
  uint64_t anon = 0, file = 0, shmem = 0;
  uint64_t anon_exec = 0;  // of anon: executable mappings of no file, a JIT's code (lavapipe's LLVM shader variants)
};
ResidentKinds resident_kinds() {
  std::ifstream status("/proc/self/status");
  ResidentKinds r;
  std::string key;
  uint64_t kb = 0;
  while (status >> key) {
    if (key == "RssAnon:" || key == "RssFile:" || key == "RssShmem:") {
      status >> kb;
      (key == "RssAnon:" ? r.anon : key == "RssFile:" ? r.file : r.shmem) = kb * 1024;
    }
    status.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  // /proc/self/smaps: a mapping's header "start-end perms offset dev inode [path]", then "Rss: N kB" among its fields.
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool jit = false;
  while (std::getline(smaps, line)) {
    if (!line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) && line.find('-') < line.find(' ')) {
      std::istringstream h(line);
      std::string range, perms, offset, dev, inode, path;
      h >> range >> perms >> offset >> dev >> inode >> path;
      jit = perms.size() >= 3 && perms[2] == 'x' && (path.empty() || path[0] == '[') && path != "[vdso]" && path != "[vsyscall]";
    } else if (jit && line.rfind("Rss:", 0) == 0) {
      r.anon_exec += std::stoull(line.substr(4)) * 1024;
    }
  }
  return r;
}

// Where resident memory sits, to tell a leak from fragmentation: bytes malloc hands out (in use), bytes its heaps hold
// from the system (arena; what is free inside them only fragments), and large blocks it mapped on its own. What
// resident memory holds beyond those (code, a JIT's output, mapped files) is mapped outside malloc.
struct HeapStats {
  uint64_t in_use = 0, arena = 0, mapped = 0;
};
HeapStats heap_stats() {
  const struct mallinfo2 m = mallinfo2();
  return {uint64_t(m.uordblks) + uint64_t(m.hblkhd), uint64_t(m.arena), uint64_t(m.hblkhd)};
}

struct Times {
  double mean = 0, median = 0;
};

// The window being played: what is sampled every frame, in storage reserved once, so that the soak's own records
// allocate nothing during a lap (a block the heap hands out mid-lap can pin the top of a heap that a driver's
// compile grew, and resident memory then steps up for the soak's sake, not the engine's).
struct FrameSamples {
  std::vector<double> cpu, gpu, wall;
  std::map<std::string, double> pass_ms;  // summed; values zeroed at a window's end, names kept
  std::map<std::string, uint64_t> states;  // frames in each weather state; zeroed at a window's end, names kept
  void reserve(size_t frames) {
    cpu.reserve(frames);
    gpu.reserve(frames);
    wall.reserve(frames);
  }
};

struct Window {
  uint64_t first_frame = 0, frames = 0;
  uint64_t rss = 0, gpu_allocated = 0, gpu_reserved = 0;
  ResidentKinds rss_kinds;
  HeapStats heap;
  std::map<std::string, uint64_t> gpu_by_name;
  cumulo::render::FrameRenderer::GraphCache graph;
  size_t pipelines = 0;
  gpu::LiveObjects objects;
  uint64_t validation_errors = 0, validation_warnings = 0;  // in this window
  uint64_t nonfinite_frames = 0, nonfinite_pixels = 0, probed_frames = 0;
  Times cpu, gpu, wall;  // ms over the window's frames
  std::set<std::string> states;
  uint32_t events = 0;
  std::map<std::string, double> pass_ms;  // summed over the window's frames
  std::vector<std::string> new_pipelines;  // made in this window (keys: shaders and defines)
};

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}
double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The level's gameplay the soak drives: events whose triggers strike lightning, the Stormbird's kill and reset, and
// the growing clouds' reset and start (each lap grows them again from their first step).
struct Gameplay {
  std::vector<std::string> lightning, killed, reset, growth_reset, growth_start;
};
Gameplay find_gameplay(const ecs::World& world) {
  Gameplay g;
  world.each_entity([&](ecs::Entity e) {
    if (const auto* t = world.try_get<gameplay::Trigger>(e); t && t->when == gameplay::Trigger::When::Event && !t->once)
      for (const gameplay::TriggerAction& a : t->actions)
        if (a.kind == gameplay::TriggerAction::Kind::StrikeLightning) {
          g.lightning.push_back(t->event);
          break;
        }
    if (const auto* s = world.try_get<gameplay::StormbirdDissipation>(e)) {
      g.killed.push_back(s->event);
      g.reset.push_back(s->reset_event);
    }
    if (const auto* c = world.try_get<gameplay::CloudGrowth>(e)) {
      if (!c->reset_event.empty()) g.growth_reset.push_back(c->reset_event);
      if (!c->event.empty()) g.growth_start.push_back(c->event);
    }
  });
  return g;
}

struct Check {
  std::string name, detail;
  bool pass = true, counted = true;  // counted: decides the exit code
};

std::vector<Check> run_checks(const std::vector<Window>& w, bool validation, bool strict_timing) {
  std::vector<Check> checks;
  auto add = [&](std::string name, bool pass, std::string detail, bool counted = true) {
    checks.push_back({std::move(name), std::move(detail), pass, counted});
  };
  auto flat = [&](const char* name, auto get) {
    bool same = true;
    std::string values;
    for (const Window& x : w) {
      same = same && get(x) == get(w.front());
      values += (values.empty() ? "" : " ") + std::to_string(get(x));
    }
    add(name, same, values);
  };
  if (w.size() >= 2) {
    const int64_t growth = int64_t(w.back().rss) - int64_t(w.front().rss);
    auto grew = [&](uint64_t ResidentKinds::*k) { return int64_t(w.back().rss_kinds.*k) - int64_t(w.front().rss_kinds.*k); };
    add("resident memory growth after the first window < 1 MB", !validation && growth < 1000000,
        validation ? "not measured: validation layers on (run without CUMULO_VALIDATION)"
                   : std::to_string(growth) + " bytes (anonymous " + std::to_string(grew(&ResidentKinds::anon)) +
                         " of which executable code of no file " + std::to_string(grew(&ResidentKinds::anon_exec)) +
                         ", file-backed " + std::to_string(grew(&ResidentKinds::file)) + ", shared " +
                         std::to_string(grew(&ResidentKinds::shmem)) + ")",
        !validation);
    // The render graph keeps up to Executor::kMaxLayouts transient layouts (and kMaxShapes compiled shapes), least
    // recently used out: which are held at a window's end depends on the frames before it, so what is checked flat
    // is the rest (the layouts held and how many were made are reported beside).
    flat("GPU memory outside the render graph's shape cache flat (bytes)",
         [](const Window& x) { return x.gpu_allocated - x.graph.transient_bytes; });
    auto outside_graph = [](const Window& x) {
      std::map<std::string, uint64_t> m;
      for (const auto& [name, bytes] : x.gpu_by_name)
        if (name.rfind("graph ", 0) != 0 && name.rfind("graph:", 0) != 0) m[name] = bytes;
      return m;
    };
    bool same_names = true;
    for (const Window& x : w) same_names = same_names && outside_graph(x) == outside_graph(w.front());
    add("GPU memory per resource flat (outside the shape cache)", same_names,
        std::to_string(outside_graph(w.front()).size()) + " resources");
    flat("render graph shapes flat", [](const Window& x) { return uint64_t(x.graph.shapes); });
    flat("render graph transient layouts flat", [](const Window& x) { return uint64_t(x.graph.layouts); });
    flat("pipelines flat", [](const Window& x) { return uint64_t(x.pipelines); });
    flat("descriptor sets flat", [](const Window& x) { return uint64_t(x.objects.descriptor_sets); });
    flat("images outside the shape cache flat", [](const Window& x) { return uint64_t(x.objects.images) - x.graph.transient_images; });
    flat("buffers flat", [](const Window& x) { return uint64_t(x.objects.buffers); });
  } else {
    add("growth", true, "not measured: fewer than two windows", false);
  }
  uint64_t errors = 0, bad = 0;
  for (const Window& x : w) errors += x.validation_errors, bad += x.nonfinite_frames;
  add("0 validation messages", errors == 0, validation ? std::to_string(errors) + " errors" : "not measured: validation layers off",
      validation);
  add("0 non-finite frames", bad == 0, std::to_string(bad) + " frames");
  if (w.size() >= 3) {
    const double second = w[1].wall.mean, last = w.back().wall.mean;
    const double change = second > 0 ? (last - second) / second : 0.0;
    char text[96];
    std::snprintf(text, sizeof text, "%.2f -> %.2f ms (%+.1f %%)", second, last, 100.0 * change);
    add("last window's frame time within 10 % of the second's", std::abs(change) <= 0.10, text, strict_timing);
  }
  return checks;
}

nlohmann::ordered_json window_json(const Window& x) {
  nlohmann::ordered_json j;
  j["first_frame"] = x.first_frame;
  j["frames"] = x.frames;
  j["resident_bytes"] = x.rss;
  j["resident_anonymous_bytes"] = x.rss_kinds.anon;
  j["resident_file_bytes"] = x.rss_kinds.file;
  j["resident_shared_bytes"] = x.rss_kinds.shmem;
  j["resident_anonymous_executable_bytes"] = x.rss_kinds.anon_exec;
  j["heap_in_use_bytes"] = x.heap.in_use;
  j["heap_arena_bytes"] = x.heap.arena;
  j["heap_mapped_bytes"] = x.heap.mapped;
  j["gpu_allocated_bytes"] = x.gpu_allocated;
  j["gpu_reserved_bytes"] = x.gpu_reserved;
  j["gpu_bytes_by_resource"] = x.gpu_by_name;
  j["graph_shapes"] = x.graph.shapes;
  j["graph_compiles"] = x.graph.compiles;
  j["graph_shapes_seen"] = x.graph.seen;
  j["graph_layouts"] = x.graph.layouts;
  j["graph_layouts_created"] = x.graph.layouts_created;
  j["graph_transient_bytes"] = x.graph.transient_bytes;
  j["graph_transient_images"] = x.graph.transient_images;
  j["pipelines"] = x.pipelines;
  j["pipelines_made"] = x.new_pipelines;
  j["descriptor_pools"] = x.objects.descriptor_pools;
  j["descriptor_sets"] = x.objects.descriptor_sets;
  j["images"] = x.objects.images;
  j["buffers"] = x.objects.buffers;
  j["vk_pipelines"] = x.objects.pipelines;
  j["validation_errors"] = x.validation_errors;
  j["validation_warnings"] = x.validation_warnings;
  j["nonfinite_frames"] = x.nonfinite_frames;
  j["nonfinite_pixels"] = x.nonfinite_pixels;
  j["probed_frames"] = x.probed_frames;
  j["cpu_ms"] = {{"mean", x.cpu.mean}, {"median", x.cpu.median}};
  j["gpu_ms"] = {{"mean", x.gpu.mean}, {"median", x.gpu.median}};
  j["frame_ms"] = {{"mean", x.wall.mean}, {"median", x.wall.median}};
  j["weather_states"] = x.states;
  j["events_fired"] = x.events;
  // The passes' mean GPU ms over the window's frames (a pass absent from a frame counts 0 there), dearest first.
  std::vector<std::pair<std::string, double>> passes(x.pass_ms.begin(), x.pass_ms.end());
  std::sort(passes.begin(), passes.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  nlohmann::ordered_json p = nlohmann::ordered_json::object();
  for (const auto& [name, ms] : passes) p[name] = ms / double(std::max<uint64_t>(1, x.frames));
  j["pass_mean_ms"] = p;
  return j;
}

void print_table(const std::vector<Window>& windows) {
  std::printf("| frames | resident MB | heap MB (in use / held) | GPU MB | graph shapes (compiles) / layouts (made) | pipelines | descriptor sets | images | buffers | "
              "CPU ms | GPU ms | frame ms (mean / median) | validation | non-finite frames | weather states |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Window& x : windows) {
    std::string states;
    for (const std::string& s : x.states) states += (states.empty() ? "" : ", ") + s;
    std::printf("| %llu-%llu | %.2f | %.2f / %.2f | %.2f | %zu (%u) / %zu (%u) | %zu | %lld | %lld | %lld | %.2f | %.2f | %.2f / %.2f | %llu | %llu | %s |\n",
                (unsigned long long)x.first_frame + 1, (unsigned long long)(x.first_frame + x.frames), x.rss / 1e6,
                x.heap.in_use / 1e6, (x.heap.arena + x.heap.mapped) / 1e6, x.gpu_allocated / 1e6, x.graph.shapes, x.graph.compiles, x.graph.layouts, x.graph.layouts_created, x.pipelines, (long long)x.objects.descriptor_sets,
                (long long)x.objects.images, (long long)x.objects.buffers, x.cpu.median, x.gpu.median, x.wall.mean,
                x.wall.median, (unsigned long long)x.validation_errors, (unsigned long long)x.nonfinite_frames,
                states.c_str());
  }
}

int run_soak(const SoakOptions& o, const CloudsRun& clouds) {
  render::CloudFeature& feature = clouds.feature;
  app::HeadlessSessionDesc d;
  d.sim.level = o.level;
  d.sim.modules = clouds.modules;
  d.width = o.width;
  d.height = o.height;
  app::HeadlessSession session(d);
  // Device memory that is host memory (lavapipe) becomes resident page by page as blocks reserved long ago
  // fill up, which reads as growth with nothing leaking: committed up front, the resident figure is host
  // memory's alone (device memory is measured apart: GPU allocated and reserved bytes).
  const bool committed = session.ctx().info().is_cpu() && session.ctx().allocator().commit_blocks();
  if (committed) std::fprintf(stderr, "cumulo soak: device memory is host memory here: its blocks are committed as reserved\n");
  cumulo::render::NonFiniteProbe probe;
  session.renderer().add_feature(probe);  // last: it sees the scene colour after the clouds
  app::Simulation& sim = session.sim();
  ecs::World& world = sim.world();

  const soak::SoakPath path = soak::make_soak_path(world);
  const ecs::Entity camera = scene::first_camera(world);
  if (camera.is_null()) fail("%s: the level has no camera to fly", o.level.c_str());
  world.set_resource<app::Viewer>(app::Viewer{camera});

  // The weather: short holds and transitions; every state of the level's library forced in turn each lap.
  std::vector<std::string> states;
  if (const auto* lw = world.try_resource<weather::LevelWeather>(); lw && lw->library) states = lw->library->ids();
  bool has_scheduler = false;
  world.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& s) {
    if (o.weather) {
      s.hold_s = {2.0f, 4.0f};
      s.transition_s = {1.0f, 2.0f};
    }
    has_scheduler = true;
  });
  if (!has_scheduler || !o.weather) states.clear();
  const LapPlan plan{o.lap, states.size(), o.modes, o.debug_views, o.day};
  float start_hours = 12.0f;
  world.view<const scene::TimeOfDay>().each([&](const scene::TimeOfDay& t) { start_hours = t.hours; });
  const double lap_seconds = plan.seconds();
  world.view<scene::TimeOfDay>().each([&](scene::TimeOfDay& t) { t.hours_per_second = 0.0f; });
  const Gameplay gameplay = o.gameplay ? find_gameplay(world) : Gameplay{};

  std::fprintf(stderr,
               "cumulo soak: %s, %ux%u, %u frames in laps of %u (%.0f m of path through %zu points, %.1f s of play a lap); "
               "%zu weather states, %zu lightning events, %zu Stormbird%s; validation %s\n",
               o.level.c_str(), o.width, o.height, o.frames, o.lap, path.length(), path.points().size(), lap_seconds,
               states.size(), gameplay.lightning.size(), gameplay.killed.size(), gameplay.killed.size() == 1 ? "" : "s",
               session.ctx().validation_enabled() ? "on" : "off");

  std::vector<Window> windows;
  Window cur;
  FrameSamples samples;
  samples.reserve(o.lap);
  uint64_t errors_before = session.ctx().validation_errors(), warnings_before = session.ctx().validation_warnings();
  cumulo::render::NonFiniteProbe::Counts probe_before;
  uint64_t bad_frames_seen = 0, bad_pixels_seen = 0;
  double step_debt = 0.0;
  size_t pipelines_seen = 0;
  uint64_t heap_high = 0;
  const Stopwatch total;
  for (uint32_t f = 0; f < o.frames; ++f) {
    const uint32_t k = f % o.lap;
    const int hz = plan.mode(k);
    feature.options().debug = plan.debug(k);
    auto fire = [&](const std::string& name) {
      app::schedule_event(world, name, sim.sim_seconds());
      ++cur.events;
    };
    // Which lightning event by the frame of the lap, so every lap strikes the same way at the same hours (a count
    // over the run made the second lap's night strikes other bolts, whose pipelines only that lap made).
    if (k % kLightningEvery == kLightningEvery / 2 && !gameplay.lightning.empty())
      fire(gameplay.lightning[(k / kLightningEvery) % gameplay.lightning.size()]);
    if (k == o.lap * 3 / 10)
      for (const std::string& e : gameplay.killed) fire(e);
    if (k == o.lap * 7 / 10)
      for (const std::string& e : gameplay.reset) fire(e);
    if (k == 0) {
      for (const std::string& e : gameplay.growth_reset) fire(e);
      for (const std::string& e : gameplay.growth_start) fire(e);
    }
    // Every lap plays the same: the weather restarts in the first state with its random stream seeded again, and the
    // level's triggers are re-armed (a trigger that fires once, the storm's entry, fires once a lap).
    if (k == 0) {
      world.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& w) {
        if (states.empty()) return;
        w.started = false;
        w.start = states.front();
        w.encounter_active = false;
      });
      world.view<gameplay::Trigger>().each([](gameplay::Trigger& t) { t.inside = t.fired = t.primed = false; });
    }
    if (const int s = plan.forced_state(k); s >= 0)
      world.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& w) { weather::force_state(w, states[size_t(s)]); });
    if (o.fly) world.get<scene::Transform>(camera) = path.transform(double(k) / o.lap);
    world.view<scene::TimeOfDay>().each([&](scene::TimeOfDay& t) { t.hours = plan.hours(k, start_hours); });

    const Stopwatch wall;
    step_debt += (1.0 / hz) / sim.step_seconds();
    const uint64_t steps = uint64_t(std::floor(step_debt + 1e-9));
    step_debt -= double(steps);
    sim.step(steps);
    cumulo::render::FrameSnapshot snapshot = session.extract(camera, cumulo::render::BudgetMode(hz));
    session.submit(snapshot);
    samples.cpu.push_back(wall.ms());
    session.wait_frame();
    samples.wall.push_back(wall.ms());
    double gpu_ms = 0;
    for (const auto& [name, ms] : session.pass_timings()) {
      gpu_ms += ms;
      samples.pass_ms[name] += ms;
    }
    samples.gpu.push_back(gpu_ms);
    // A frame holding a NaN or an infinity is named with its state, so it can be found again (the table counts them).
    if (const auto now = probe.counts(); now.bad_frames > bad_frames_seen) {
      bad_frames_seen = now.bad_frames;
      const uint64_t pixels = now.bad_pixels - bad_pixels_seen;
      bad_pixels_seen = now.bad_pixels;
      std::string state;
      world.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& w) { state = w.current; });
      const scene::Transform& t = world.get<scene::Transform>(camera);
      const glm::vec3 at = t.position, ahead = t.forward();
      std::fprintf(stderr, "cumulo soak: frame %u (lap %u, frame %u of it) holds %llu non-finite pixel(s), the first at "
                   "(%d, %d): %d Hz, debug view %s, weather %s, %.2f h, camera at (%.9g, %.9g, %.9g) looking (%.4f, %.4f, "
                   "%.4f), rotation (w x y z) %.9g %.9g %.9g %.9g\n", f + 1, f / o.lap + 1, k + 1, (unsigned long long)pixels,
                   now.last_bad_pixel.x, now.last_bad_pixel.y, hz, render::debug_view_name(plan.debug(k)), state.c_str(),
                   plan.hours(k, start_hours), at.x, at.y, at.z, ahead.x, ahead.y, ahead.z, t.rotation.w,
                   t.rotation.x, t.rotation.y, t.rotation.z);
    }
    if (o.trace_heap) {
      const uint64_t in_use = heap_stats().in_use;
      if (f >= o.lap && in_use >= heap_high + 8192) {
        std::string passes;
        char text[160];
        for (const auto& [name, ms] : session.pass_timings()) {
          std::snprintf(text, sizeof text, "%s%s %.1f ms", passes.empty() ? "" : ", ", name.c_str(), ms);
          passes += text;
        }
        std::string state;
        world.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& w) { state = w.current; });
        std::fprintf(stderr, "cumulo soak: heap: frame %u (lap %u, frame %u of it): in use +%.1f KB to %.2f MB; %d Hz, "
                     "debug view %s, weather %s, %.2f h; passes: %s\n", f + 1, f / o.lap + 1, k + 1,
                     (in_use - heap_high) / 1024.0, in_use / 1e6, hz, render::debug_view_name(plan.debug(k)),
                     state.c_str(), plan.hours(k, start_hours), passes.c_str());
      }
      heap_high = std::max(heap_high, in_use);
    }
    world.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& w) {
      if (!w.current.empty()) ++samples.states[w.current];
    });

    if ((f + 1) % o.lap == 0 || f + 1 == o.frames) {
      cur.first_frame = f + 1 - uint64_t(samples.wall.size());
      cur.frames = samples.wall.size();
      auto times = [](std::vector<double>& v) {
        Times t{mean_of(v), median_of(v)};
        v.clear();  // keeps its storage for the next window
        return t;
      };
      cur.cpu = times(samples.cpu);
      cur.gpu = times(samples.gpu);
      cur.wall = times(samples.wall);
      for (auto& [name, ms] : samples.pass_ms) {
        if (ms > 0) cur.pass_ms[name] = ms;
        ms = 0;
      }
      for (auto& [state, frames] : samples.states) {
        if (frames > 0) cur.states.insert(state);
        frames = 0;
      }
      cur.rss = resident_bytes();
      cur.rss_kinds = resident_kinds();
      cur.heap = heap_stats();
      const gpu::MemoryStats m = session.ctx().allocator().stats();
      cur.gpu_allocated = m.allocated_bytes;
      cur.gpu_reserved = m.reserved_bytes;
      cur.gpu_by_name = gpu::live_memory_by_name();
      cur.graph = session.renderer().graph_cache();
      cur.pipelines = session.renderer().pipeline_library().size();
      const std::vector<std::string> keys = session.renderer().pipeline_library().keys();
      cur.new_pipelines.assign(keys.begin() + std::ptrdiff_t(std::min(keys.size(), pipelines_seen)), keys.end());
      pipelines_seen = keys.size();
      cur.objects = gpu::live_objects();
      cur.validation_errors = session.ctx().validation_errors() - errors_before;
      cur.validation_warnings = session.ctx().validation_warnings() - warnings_before;
      errors_before = session.ctx().validation_errors();
      warnings_before = session.ctx().validation_warnings();
      const auto counts = probe.counts();
      cur.probed_frames = counts.frames - probe_before.frames;
      cur.nonfinite_frames = counts.bad_frames - probe_before.bad_frames;
      cur.nonfinite_pixels = counts.bad_pixels - probe_before.bad_pixels;
      probe_before = counts;
      std::fprintf(stderr,
                   "cumulo soak: [%llu/%u] %.0f s: resident %.2f MB (%.2f anonymous, %.2f of it code; %.2f file-backed; heap: %.2f MB in use, %.2f MB held), GPU %.2f MB, %zu graph shapes (%zu seen, %zu layouts, %u made), %zu pipelines, "
                   "%lld images, frame %.2f ms (median), %llu validation errors, %llu non-finite frames\n",
                   (unsigned long long)(f + 1), o.frames, total.seconds(), cur.rss / 1e6, cur.rss_kinds.anon / 1e6,
                   cur.rss_kinds.anon_exec / 1e6, cur.rss_kinds.file / 1e6, cur.heap.in_use / 1e6,
                   (cur.heap.arena + cur.heap.mapped) / 1e6, cur.gpu_allocated / 1e6,
                   cur.graph.shapes, cur.graph.seen, cur.graph.layouts, cur.graph.layouts_created, cur.pipelines, (long long)cur.objects.images, cur.wall.median,
                   (unsigned long long)cur.validation_errors, (unsigned long long)cur.nonfinite_frames);
      windows.push_back(std::move(cur));
      cur = Window{};
    }
  }
  feature.options().debug = render::CloudDebugView::None;
  const bool validation = session.ctx().validation_enabled();
  const std::vector<Check> checks = run_checks(windows, validation, o.strict_timing);
  const gpu::DeviceInfo& device = session.ctx().info();

  std::printf("## cumulo soak: %s, %s, %ux%u, %u frames, laps of %u, validation %s (%.0f s)\n\n", o.level.c_str(),
              device.name.c_str(), o.width, o.height, o.frames, o.lap, validation ? "on" : "off", total.seconds());
  print_table(windows);
  std::printf("\n");
  bool failed = false;
  for (const Check& c : checks) {
    std::printf("- %s %s: %s%s\n", c.pass ? "PASS" : (c.counted ? "FAIL" : "----"), c.name.c_str(), c.detail.c_str(),
                c.counted || c.pass ? "" : " (not counted)");
    failed = failed || (c.counted && !c.pass);
  }
  if (!o.out.empty()) {
    nlohmann::ordered_json j;
    j["level"] = o.level;
    j["device"] = {{"name", device.name}, {"driver", device.driver_info}};
    j["size"] = {o.width, o.height};
    j["frames"] = o.frames;
    j["lap_frames"] = o.lap;
    j["lap_seconds"] = lap_seconds;
    j["path_m"] = path.length();
    j["validation_enabled"] = validation;
    j["device_memory_committed"] = committed;
    j["wall_seconds"] = total.seconds();
    j["weather_states"] = states;
    nlohmann::ordered_json w = nlohmann::ordered_json::array();
    for (const Window& x : windows) w.push_back(window_json(x));
    j["windows"] = w;
    nlohmann::ordered_json c = nlohmann::ordered_json::array();
    for (const Check& x : checks) c.push_back({{"check", x.name}, {"pass", x.pass}, {"counted", x.counted}, {"detail", x.detail}});
    j["checks"] = c;
    write_file_atomic(o.out, j.dump(2) + "\n");
    std::printf("cumulo soak: wrote %s\n", o.out.c_str());
  }
  const int code = session.finish();
  if (code != 0) return code;
  return failed ? 4 : 0;
}

}  // namespace

void register_soak_command(CommandRegistry& registry, const CloudsRun& clouds) {
  registry.add({"soak", "fly a loop through a level for many frames with everything switched on; check nothing grows",
                [clouds](int argc, char** argv) {
                  SoakOptions o;
                  std::string size, level, modes, debug_views, weather, gameplay, day, fly;
                  ArgParser p("cumulo soak",
                              "Headless soak run: a camera loop through the level's cameras and weather zones, the weather\n"
                              "scheduler on short holds with every state forced in turn, a day a lap (3 h steps, a sweep at dusk), lightning every 1.5 s,\n"
                              "the Stormbird killed and reset, budget modes 30/40/60 and the debug views switched. Each lap\n"
                              "records resident and GPU memory, graph shapes, pipelines, descriptor sets, images, frame times,\n"
                              "validation messages and non-finite frames. Exit 4 when something grew (or, with\n"
                              "--strict-timing, the last lap is more than 10 % slower or faster than the second), 3 on\n"
                              "validation errors.");
                  p.positional("LEVEL", "level file (default content/levels/sample/level.json)", &level, false)
                      .option("--frames", "N", "frames to render (default 10000)", &o.frames)
                      .option("--lap", "N", "frames per lap of the path and per window of the report (default 1000)", &o.lap)
                      .option("--size", "WxH", "render size (default 160x90)", &size)
                      .option("--out", "FILE.json", "write every window and the checks as JSON", &o.out)
                      .option("--modes", "30,40,60", "budget modes a lap switches between (default 30,40,60)", &modes)
                      .option("--debug-views", "on|off", "switch the clouds' debug views once a lap (default on)", &debug_views)
                      .option("--weather-cycle", "on|off", "the scheduler on short holds, every weather state forced in turn (default on)", &weather)
                      .option("--gameplay", "on|off", "lightning and the Stormbird's kill and reset (default on)", &gameplay)
                      .option("--fly", "on|off", "fly the loop (default on; off: the level's first camera stands still)", &fly)
                      .option("--day", "on|off", "a day each lap (default on; off: the level's time of day)", &day)
                      .flag("--strict-timing", "the frame-time check decides the exit code too", &o.strict_timing)
                      .flag("--trace-heap",
                            "after the first lap, print each frame where malloc's bytes in use reach a new high (by 8 KB "
                            "or more), with what the frame did: where a leak or a driver's cache grows",
                            &o.trace_heap);
                  clouds.add_run_options(p);
                  if (!p.parse(argc, argv)) return 0;
                  if (!level.empty()) o.level = level;
                  if (!size.empty()) app::parse_size(size, o.width, o.height);
                  if (!modes.empty()) {
                    o.modes.clear();
                    std::stringstream ss(modes);
                    for (std::string m; std::getline(ss, m, ',');)
                      o.modes.push_back(cumulo::render::budget_hz(cumulo::render::parse_budget_mode(m)));
                    if (o.modes.empty()) fail("--modes: no mode named");
                  }
                  auto on_off = [](const char* flag, const std::string& v, bool& out) {
                    if (v.empty()) return;
                    if (v != "on" && v != "off") fail("%s: expected on or off, got \"%s\"", flag, v.c_str());
                    out = v == "on";
                  };
                  on_off("--debug-views", debug_views, o.debug_views);
                  on_off("--weather-cycle", weather, o.weather);
                  on_off("--gameplay", gameplay, o.gameplay);
                  on_off("--day", day, o.day);
                  on_off("--fly", fly, o.fly);
                  if (o.lap < 60 || o.lap > 1000000) fail("--lap: %u is outside 60..1000000", o.lap);
                  if (o.frames < 1 || o.frames > 10000000) fail("--frames: %u is outside 1..10000000", o.frames);
                  return run_soak(o, clouds);
                }});
}

}  // namespace cumulo::clouds
