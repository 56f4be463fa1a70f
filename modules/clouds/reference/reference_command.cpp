// `cumulo reference`: the path-traced reference image of a level's view (render/reference_tracer.h).
#include "modules/clouds/reference/reference_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/app/run_options.h"
#include "engine/core/args.h"
#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "modules/clouds/reference/exr_file.h"
#include "modules/clouds/reference/fidelity_metrics.h"
#include "modules/clouds/reference/render_session.h"

namespace cumulo::clouds {

void add_reference_options(ArgParser& p, ReferenceOptions& o) {
  p.option("--spp", "N", "samples per pixel (default 256)", &o.spp)
      .option("--max-bounces", "K", "scattering events per path (default 64; 1: single scattering)", &o.max_bounces)
      .option("--phase", "cloud|mie",
              "phase function: the real-time march's dual-lobe HG (default, isolates the lighting model) or "
              "Jendersie & d'Eon 2023's approximate Mie for 20 um droplets",
              &o.phase_text)
      .option("--seed", "S", "random seed (default 1; the same seed gives the same image)", &o.seed);
}

void check_reference_options(ReferenceOptions& o) {
  if (o.spp < 1 || o.spp > 1000000) fail("--spp: %u is outside 1..1000000", o.spp);
  if (o.max_bounces < 1 || o.max_bounces > 4096) fail("--max-bounces: %u is outside 1..4096", o.max_bounces);
  // Isotropic is the tests' phase, not a choice of the command.
  constexpr std::array kPhases{render::kReferencePhaseNames[0], render::kReferencePhaseNames[1]};
  o.phase = parse_name_or_fail(kPhases, "--phase", o.phase_text);
}

render::ReferenceImage accumulate_reference(RenderSession& session, render::ReferenceTracer& tracer, ecs::Entity camera,
                                            const ReferenceOptions& o, const std::string& label, double* seconds) {
  render::ReferenceSettings& s = tracer.settings();
  s.max_bounces = o.max_bounces;
  s.phase = o.phase;
  s.seed = o.seed;
  tracer.reset();
  Stopwatch clock;
  double last_print = -10.0;
  // Samples per frame grow while a frame stays under about a second (fewer submits; progress stays live).
  uint32_t per_frame = 1;
  while (tracer.samples() < o.spp) {
    s.samples_per_frame = std::min(per_frame, o.spp - tracer.samples());
    Stopwatch frame;
    session.render(camera);
    const double ms = frame.ms();
    if (ms < 500.0 && per_frame < 64) per_frame *= 2;
    const double t = clock.seconds();
    if (t - last_print >= 2.0 || tracer.samples() >= o.spp) {
      const double eta = t / double(tracer.samples()) * double(o.spp - tracer.samples());
      std::fprintf(stderr, "cumulo reference: %s: %u/%u spp (%.0f %%), %.1f s, ETA %.0f s\n", label.c_str(), tracer.samples(),
                   o.spp, 100.0 * tracer.samples() / o.spp, t, eta);
      last_print = t;
    }
  }
  if (seconds) *seconds = clock.seconds();
  render::ReferenceImage img = tracer.read();
  if (img.majorant_violations > 0)
    std::fprintf(stderr, "cumulo reference: warning: %.0f density samples above the majorant grid (the image is biased)\n",
                 img.majorant_violations);
  return img;
}

namespace {

int run_reference(const std::string& level, const std::string& camera_name, std::optional<float> tod, uint32_t w, uint32_t h,
                  const ReferenceOptions& o, const std::string& out, const CloudsRun& run) {
  RenderSessionDesc d;
  d.level = level;
  d.width = w, d.height = h;
  d.time_of_day = tod;
  RenderSession session(d, run);
  render::ReferenceTracer tracer(session.ctx(), run.feature.pipeline_library());
  run.feature.set_reference(&tracer);
  const ecs::Entity camera = session.camera(camera_name);
  double seconds = 0;
  const render::ReferenceImage img = accumulate_reference(session, tracer, camera, o, camera_name.empty() ? "default camera" : camera_name, &seconds);
  run.feature.set_reference(nullptr);
  write_exr(out, img.width, img.height, img.radiance);
  namespace fs = std::filesystem;
  const fs::path png = fs::path(out).replace_extension(".png");
  gpu::write_png(png, session.screenshot());
  // Convergence: the mean relative standard error of the pixel luminance, in cloud and overall.
  double se_cloud = 0, se_all = 0;
  uint64_t n_cloud = 0;
  for (size_t i = 0; i < img.radiance.size(); ++i) {
    const double L = std::max(1e-4f, luminance(glm::vec3(img.radiance[i])));
    const double rel = img.luminance_stderr[i] / L;
    se_all += rel;
    if (img.radiance[i].a >= kCloudOpacity) se_cloud += rel, ++n_cloud;
  }
  std::printf("cumulo reference: %ux%u, %u spp, %u bounces, phase %s on %s: %.1f s (%.1f ms per spp, %.2f s per 1000 spp per "
              "megapixel)\n",
              img.width, img.height, img.samples, o.max_bounces, render::reference_phase_name(o.phase),
              session.ctx().info().name.c_str(), seconds, 1000.0 * seconds / img.samples,
              seconds / img.samples * 1000.0 / (double(img.width) * img.height / 1e6));
  std::printf("cumulo reference: per-pixel standard error of the luminance: %.1f %% in cloud (%llu px), %.1f %% overall\n",
              n_cloud ? 100.0 * se_cloud / double(n_cloud) : 0.0, (unsigned long long)n_cloud,
              100.0 * se_all / double(std::max<size_t>(1, img.radiance.size())));
  std::printf("cumulo reference: wrote %s and %s\n", out.c_str(), png.string().c_str());
  if (session.ctx().validation_errors() > 0) {
    std::fprintf(stderr, "cumulo reference: %u Vulkan validation errors (last: %s)\n", session.ctx().validation_errors(),
                 session.ctx().last_validation_message().c_str());
    return 3;
  }
  return 0;
}

}  // namespace

void register_reference_command(CommandRegistry& registry, const CloudsRun& run) {
  registry.add({"reference", "path-trace a view of a level: the ground truth of the cloud lighting (EXR + PNG)",
                [run](int argc, char** argv) {
                  std::string level, camera, size, out, tod_text;
                  ReferenceOptions o;
                  ArgParser p("cumulo reference",
                              "Path-trace a view of a level on the Vulkan device: delta tracking through the real-time\n"
                              "march's density field, the same sun, the atmosphere's sky, the terrain as a Lambertian\n"
                              "heightfield. Writes linear HDR (OpenEXR; alpha = the clouds' opacity) and a tonemapped PNG\n"
                              "beside it. Deterministic for a seed.");
                  p.positional("LEVEL", "level.json", &level)
                      .option("--camera", "NAME", "camera of the level (default: its first)", &camera)
                      .option("--time-of-day", "H", "hours 0..24 (default: the level's)", &tod_text)
                      .option("--size", "WxH", "image size (default 320x180)", &size)
                      .option("-o", "OUT.exr", "output image (required)", &out);
                  add_reference_options(p, o);
                  if (!p.parse(argc, argv)) return 0;
                  check_reference_options(o);
                  if (out.empty()) fail("cumulo reference: -o OUT.exr is required");
                  uint32_t w = 320, h = 180;
                  if (!size.empty()) app::parse_size(size, w, h);
                  std::optional<float> tod;
                  if (!tod_text.empty()) {
                    char* end = nullptr;
                    const float v = std::strtof(tod_text.c_str(), &end);
                    if (!end || *end || !(v >= 0.0f && v <= 24.0f)) fail("--time-of-day: expected hours 0..24, got \"%s\"", tod_text.c_str());
                    tod = v;
                  }
                  return run_reference(level, camera, tod, w, h, o, out, run);
                }});
}

}  // namespace cumulo::clouds
