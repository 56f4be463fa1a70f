// The windowed loop of `cumulo run`: GLFW window, swapchain with resize, frames paced to the budget
// mode, the fly camera, shader hot reload. Simulation steps follow real time in fixed steps.
#include <algorithm>
#include <chrono>
#include <limits>
#include <cstdio>
#include <thread>

#include "engine/app/detail/run_context.h"
#include "engine/app/recording.h"
#include "engine/app/frame_output.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/readback.h"
#include "engine/gpu/swapchain.h"
#include "engine/platform/window.h"
#include "engine/render/frame_renderer.h"

namespace cumulo::app::detail {
namespace {

std::unique_ptr<platform::Window> open_window(const RunOptions& o, const std::string& level_name) {
  try {
    platform::WindowDesc wd;
    wd.title = "cumulo - " + level_name;
    wd.width = o.width;
    wd.height = o.height;
    return platform::Window::create(wd);
  } catch (const Error& e) {
    throw WindowUnavailable(e.what());
  }
}

VkExtent2D window_extent(const platform::Window& w) { return {w.width(), w.height()}; }

}  // namespace

int run_windowed(RunContext& rc) {
  const RunOptions& o = rc.opt;
  std::vector<std::string> extensions;
  try {
    for (const char* e : platform::Window::required_vulkan_extensions()) extensions.emplace_back(e);
  } catch (const Error& e) {
    throw WindowUnavailable(e.what());
  }
  auto window = open_window(o, rc.sim.level().name.empty() ? o.level : rc.sim.level().name);

  gpu::ContextDesc cd;
  cd.instance_extensions = extensions;
  cd.need_present = true;
  cd.create_surface = [&](VkInstance instance) { return window->create_surface(instance); };
  gpu::Context ctx(cd);
  LOG_INFO("device: %s (%s); window %ux%u, %s; Esc quits, right mouse or Tab looks, WASD/QE fly, Shift fast",
           ctx.info().name.c_str(), ctx.info().driver_info.c_str(), window->width(), window->height(),
           render::budget_mode_name(o.mode));
  window->wait_while_minimized();
  gpu::Swapchain swapchain(ctx, window_extent(*window), gpu::SwapchainDesc{});
  render::FrameRenderer renderer(ctx);
  renderer.set_aerial_perspective_lut(rc.opt.aerial_lut);
  renderer.set_lod_error_px(rc.opt.lod_error_px);
  add_module_features(rc, renderer);
  gpu::FrameRing frames(ctx);
  // Modules' UIs live from here until the guard goes (first of all, device idle, before the renderer).
  configure_resolution(rc, ctx, true);
  WindowServices services{*window, ctx, renderer, rc.opt.mode, rc.resolution};
  struct UiGuard {
    gpu::Context& ctx;
    const Modules& modules;
    ~UiGuard() {
      ctx.wait_idle();
      for (const auto& m : modules) m->on_window_close();
    }
  } ui_guard{ctx, rc.modules};
  for (const auto& m : rc.modules) m->on_window_open(services);

  FlyCamera fly = fly_camera_from(rc.sim.world(), rc.camera);
  platform::InputState input;
  const double target_s = render::budget_frame_seconds(o.mode);
  Stopwatch frame_clock, title_clock;
  uint64_t rendered = 0;
  uint64_t resolution_frame = 0;  // the last completed frame fed to the dynamic resolution
  render::FrameSnapshot last;
  bool dumped = false;

  while (o.frames == 0 || rendered < o.frames) {
    double dt = frame_clock.seconds();
    frame_clock.reset();
    Stopwatch cpu;
    window->poll(input);
    // A module's UI goes first: keys typed into its text field or a drag over its panel are not the camera's.
    InputClaim claim;
    for (const auto& m : rc.modules) {
      const InputClaim c = m->on_frame_input(rc.sim.world(), input, dt);
      claim.keyboard |= c.keyboard;
      claim.mouse |= c.mouse;
    }
    const platform::InputState own = unclaimed_input(input, claim);
    if (own.was_pressed(platform::Key::Escape)) window->request_close();
    if (window->should_close()) {
      bool allowed = true;
      for (const auto& m : rc.modules) allowed = m->allow_close(rc.sim.world()) && allowed;
      if (allowed) break;
      window->cancel_close();  // a module asks first (unsaved changes)
    }
    if (own.was_pressed(platform::Key::Tab)) window->set_cursor_captured(!own.cursor_captured);
    // A replay moves the camera itself (the recorded path); the keys and mouse do not.
    if (!replaying(rc.sim.world()) && update_fly_camera(fly, own, static_cast<float>(std::min(dt, 0.1))))
      apply_fly_camera(rc.sim.world(), rc.camera, fly);

    uint32_t steps = rc.clock.steps_for_real_time(dt);
    rc.sim.step(steps);
    rc.clock.on_steps_run(steps);

    if (renderer.reload_shaders()) LOG_INFO("shaders reloaded");

    if (window->consume_resized() || swapchain.needs_recreate()) {
      window->wait_while_minimized();
      if (window->should_close()) break;
      swapchain.recreate(window_extent(*window));
    }

    gpu::Frame& f = frames.begin();
    auto timings = renderer.pass_timings();  // the previous frame's, when it has completed
    if (rendered > 0) {
      rc.stats.add_gpu_frame(timings);
      rc.stats.add_resolution_scale(last.resolution_scale);
    }
    // Dynamic resolution reads each completed frame once (frames in flight: the last recorded one is rarely
    // complete here). Never the wall clock: it holds the frame pacing's sleep.
    if (auto [done, done_timings] = renderer.latest_completed_pass_timings(); done > resolution_frame) {
      resolution_frame = done;
      feed_resolution(rc, done_timings, std::numeric_limits<double>::quiet_NaN());
    }
    std::optional<uint32_t> image = swapchain.acquire(f.acquired);
    if (!image) {  // out of date: nothing was signalled; submit the empty frame to keep the ring in step
      frames.submit(f);
      swapchain.recreate(window_extent(*window));
      continue;
    }
    VkExtent2D extent = swapchain.extent();
    last = extract(rc, extent.width, extent.height, rendered + 1);
    last.resolution_scale = next_resolution_scale(rc);
    render::RenderTarget target;
    target.image = swapchain.image(*image);
    target.view = swapchain.view(*image);
    target.format = swapchain.format();
    target.extent = extent;
    target.initial = render::ResourceState::acquired();  // the whole image is rewritten: old contents discarded
    target.final = render::ResourceState::present();
    target.name = "swapchain";
    renderer.record_frame(f.cmd, last, target, f.slot);
    frames.submit(f, f.acquired, swapchain.render_finished(*image));
    swapchain.set_layout(*image, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    rc.stats.add_cpu_frame_ms(cpu.ms());
    if (!swapchain.present(*image)) swapchain.recreate(window_extent(*window));
    ++rendered;
    if (!dumped && !o.dump_graph.empty()) {
      write_graph_dump(o.dump_graph, renderer.last_compiled());
      dumped = true;
    }

    if (title_clock.seconds() > 0.5) {
      // A failed hot reload keeps the old pipeline; say so where the user is looking (details in the log).
      std::string errors = renderer.shader_errors();
      // The frame number lets a tool driving the window (tests/editor/editor_person_xvfb.sh) wait for frames.
      window->set_title(strf("cumulo - %s - %.1f ms (%s budget %.1f ms, clouds at %.0f %%) - frame %llu%s",
                             rc.sim.level().name.c_str(), dt * 1000.0, render::budget_mode_name(o.mode),
                             rc.resolution.budget_ms(o.mode), 100.0 * last.resolution_scale,
                             static_cast<unsigned long long>(rendered),
                             errors.empty() ? "" : " - SHADER ERROR, old pipeline kept (see log)"));
      title_clock.reset();
    }
    // Frame pacing: never faster than the budget mode (FIFO present also caps at the display rate).
    double left = target_s - frame_clock.seconds();
    if (left > 0.0005) std::this_thread::sleep_for(std::chrono::duration<double>(left));
  }
  frames.wait_all();
  rc.stats.add_gpu_frame(renderer.pass_timings());
  rc.stats.set_frames(rendered);

  if (!o.screenshot.empty() && rendered > 0) {
    // The swapchain images belong to the presentation engine: render the last snapshot once more offscreen.
    OffscreenOutput output(ctx, last.width, last.height);
    gpu::Frame& f = frames.begin();
    renderer.record_frame(f.cmd, last, output.target(), f.slot);
    frames.submit(f);
    frames.wait_all();
    output.after_frame();
    gpu::write_png(o.screenshot, gpu::read_image_rgba8(ctx, output.image()));
    std::printf("cumulo: wrote screenshot %s\n", o.screenshot.c_str());
  }
  write_stats(rc, ctx, swapchain.extent().width, swapchain.extent().height);
  std::printf("cumulo: %llu frames rendered in a window\n", static_cast<unsigned long long>(rendered));
  if (ctx.validation_errors() > 0) {
    LOG_ERROR("%u Vulkan validation errors (last: %s)", ctx.validation_errors(), ctx.last_validation_message().c_str());
    return 3;
  }
  return 0;
}

}  // namespace cumulo::app::detail
