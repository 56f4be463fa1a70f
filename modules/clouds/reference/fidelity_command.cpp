// `cumulo fidelity`: the real-time image of fixed views against the path-traced reference (issue 11).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "engine/app/game_events.h"
#include "engine/app/run_options.h"
#include "engine/core/args.h"
#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "engine/core/png.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "modules/clouds/reference/exr_file.h"
#include "modules/clouds/reference/fidelity_features.h"
#include "modules/clouds/reference/fidelity_metrics.h"
#include "modules/clouds/reference/reference_command.h"
#include "modules/clouds/reference/render_session.h"
#include "modules/clouds/render/cloud_passes.h"
#include "modules/clouds/render/hdr_capture.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

// One view of the fidelity set: a level camera, or a pose; its time of day; the effect it shows (switched
// off in a second real-time run to measure its contribution); an event fired first (lightning).
struct FidelityView {
  std::string name;
  std::string camera;  // a level camera, or empty with a pose
  std::optional<glm::vec3> position, look_at;
  float fov_y_deg = 60.0f;
  std::optional<float> time_of_day;
  std::string effect;  // kCloudEffects name, or empty
  std::string event;   // fired before the view's frames
  uint32_t event_steps = 0;  // simulation steps after the event (the flash's rise)
  std::string note;    // what the view shows
  // Placed by the sun (at the view's time of day): the camera `distance` m from `target` horizontally, at
  // height `height`, on the side away from the sun ("behind": the sun behind the target) or toward it
  // ("viewer": the sun behind the viewer).
  std::string sun;
  glm::vec3 target{0.0f};
  float distance = 1500.0f, height = 500.0f;
};

std::vector<FidelityView> load_views(const fs::path& file) {
  JsonDocument doc = load_json_file(file);
  const JsonView root = doc.view();
  std::vector<FidelityView> out;
  for (const JsonView& v : root["views"].elements()) {
    FidelityView f;
    f.name = v.get<std::string>("name");
    if (f.name.empty() || f.name.find_first_of("/\\ ") != std::string::npos) v["name"].fail("expected a name without spaces or slashes");
    f.camera = v.get<std::string>("camera", "");
    if (v.has("position")) {
      f.position = v["position"].as_vec3();
      f.look_at = v["look_at"].as_vec3();
    }
    f.sun = v.get<std::string>("sun", "");
    if (!f.sun.empty()) {
      if (f.sun != "behind" && f.sun != "viewer") v["sun"].fail("expected \"behind\" (the sun behind the target) or \"viewer\"");
      f.target = v["target"].as_vec3();
      f.distance = v["distance"].as_float_in(10.0f, 100000.0f);
      f.height = v["height"].as_float_in(-1000.0f, 20000.0f);
    }
    if (f.camera.empty() && !f.position && f.sun.empty()) v.fail("expected \"camera\" or \"position\" and \"look_at\"");
    if (v.has("fov_y_deg")) f.fov_y_deg = v["fov_y_deg"].as_float_in(1.0f, 170.0f);
    if (v.has("time_of_day")) f.time_of_day = v["time_of_day"].as_float_in(0.0f, 24.0f);
    f.effect = v.get<std::string>("effect", "");
    if (!f.effect.empty() && !render::cloud_effect_bit(f.effect)) v["effect"].fail("unknown effect \"" + f.effect + "\"");
    f.event = v.get<std::string>("event", "");
    f.event_steps = v.get<uint32_t>("event_steps", 0u);
    if (f.event_steps > 100000) v["event_steps"].fail("expected at most 100000 steps");
    f.note = v.get<std::string>("note", "");
    out.push_back(f);
  }
  if (out.empty()) root["views"].fail("expected at least one view");
  return out;
}

struct FidelityOptions {
  std::string level = (repo_root() / "content/levels/sample/level.json").string();
  std::string views_file;  // default: fidelity.json beside the level
  std::vector<std::string> only;
  uint32_t width = 160, height = 90;
  uint32_t warmup = 8, frames = 24;  // real-time frames: after a restart, then averaged
  ReferenceOptions ref;
  std::string out = "fidelity.json";
  std::string images;  // default: <out without extension>_images/
  bool reuse_references = false;
  std::vector<render::CloudLightingPreset> presets{render::CloudLightingPreset::Slab, render::CloudLightingPreset::Talk};
};

// The real-time image of a still view: `warmup` frames after a restart of the history, then the mean of
// `frames` frames' scene colours (temporal accumulation on, the simulation held still).
std::vector<glm::vec4> realtime_image(RenderSession& s, render::CloudFeature& f, render::HdrCapture& capture, ecs::Entity camera,
                                      const FidelityOptions& o) {
  f.set_reference(nullptr);
  f.restart_history();
  f.set_hdr_capture(nullptr);
  for (uint32_t k = 0; k < o.warmup; ++k) s.render(camera);
  f.set_hdr_capture(&capture);
  std::vector<glm::vec4> sum(size_t(s.width()) * s.height(), glm::vec4(0.0f));
  for (uint32_t k = 0; k < o.frames; ++k) {
    s.render(camera);
    const std::vector<glm::vec4> px = capture.read();
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += px[i];
  }
  f.set_hdr_capture(nullptr);
  for (glm::vec4& v : sum) v /= float(o.frames);
  return sum;
}

// The lights a reference was traced with, in its standard-error EXR's alpha (1: all, as before --cloud-lights).
float lights_tag(render::CloudLights l) { return 1.0f + float(l); }

// A previous run's reference of this view (`base`_reference.exr, _reference_stderr.exr, _reference.png) when it
// has the size, samples and lights asked for.
bool load_reference(const std::string& base, const FidelityOptions& o, render::CloudLights lights, render::ReferenceImage& ref,
                    gpu::Rgba8Image& png) {
  namespace fs = std::filesystem;
  if (!fs::exists(base + "_reference.exr") || !fs::exists(base + "_reference_stderr.exr") || !fs::exists(base + "_reference.png"))
    return false;
  uint32_t w = 0, h = 0, w2 = 0, h2 = 0;
  std::vector<glm::vec4> radiance = read_exr(base + "_reference.exr", &w, &h);
  std::vector<glm::vec4> se = read_exr(base + "_reference_stderr.exr", &w2, &h2);
  if (w != o.width || h != o.height || w2 != w || h2 != h || se.empty() || uint32_t(se[0].y) != o.ref.spp) return false;
  if (se[0].w != lights_tag(lights)) return false;
  ref.width = w, ref.height = h;
  ref.samples = uint32_t(se[0].y);
  ref.majorant_violations = se[0].z;
  ref.radiance = std::move(radiance);
  ref.luminance_stderr.resize(se.size());
  for (size_t i = 0; i < se.size(); ++i) ref.luminance_stderr[i] = se[i].x;
  ImageRgba8 px = read_png_rgba8(base + "_reference.png");
  png.width = px.width, png.height = px.height;
  png.pixels = std::move(px.rgba);
  return true;
}

// The real-time side's light grid, x (east) x z (north) x y (levels) as the talk writes 256x256x32; null without
// clouds.
nlohmann::ordered_json light_grid_json(const render::CloudFeature& f) {
  if (!f.resources()) return nullptr;
  const glm::uvec3 g = f.resources()->desc.light_grid_size;
  return {g.x, g.z, g.y};
}

struct ViewResult {
  FidelityView view;
  FidelityError err, err_off;  // the first preset's (the talks' constants by default)
  std::vector<FidelityError> preset_err;  // per preset
  std::vector<ViewFeatures> preset_features;  // per preset
  double effect_contribution = NAN;  // mean |on - off| / L_ref in cloud
  uint32_t spp = 0;
  double reference_seconds = 0;
  bool reference_reused = false;
  nlohmann::ordered_json images = nlohmann::ordered_json::object();
};

int run_fidelity(FidelityOptions& o, const CloudsRun& run) {
  const fs::path level_dir = fs::path(o.level).parent_path();
  const fs::path views_file = o.views_file.empty() ? level_dir / "fidelity.json" : fs::path(o.views_file);
  if (!fs::exists(views_file)) fail("%s: no fidelity views (give --views-file)", views_file.string().c_str());
  std::vector<FidelityView> views = load_views(views_file);
  if (!o.only.empty()) {
    std::vector<FidelityView> kept;
    for (const std::string& n : o.only) {
      auto it = std::find_if(views.begin(), views.end(), [&](const FidelityView& v) { return v.name == n; });
      if (it == views.end()) fail("--views: no view \"%s\" in %s", n.c_str(), views_file.string().c_str());
      kept.push_back(*it);
    }
    views = kept;
  }
  const fs::path images = o.images.empty() ? fs::path(fs::path(o.out).replace_extension("").string() + "_images") : fs::path(o.images);
  fs::create_directories(images);

  render::CloudFeature& feature = run.feature;
  feature.options().reference_comparable = true;
  // The lighting is measured with every pixel marched every frame (the 2023 talk's method) unless
  // --cloud-reprojection 4 or 16 asks for the 2015 talk's: in a still view the reprojection's clamp of the history
  // to the marched neighbours' range keeps 1 of 4 about 2-3 % and 1 of 16 10-20 % darker than the march (issue 21).
  if (feature.options().reprojection_block == 0) feature.options().reprojection_block = 1;
  // Likewise the talk's light grid (256x256x32, every GPU's) unless --cloud-light-grid device asks for the CPU device's
  // smaller one, a cost cut for lavapipe: its 43 m voxels over the cloudscape's 4 km smear the small clouds' sums (at
  // 256 spp `ground` 15.7 % with it, 13.2 % with the talk's; docs/fidelity/envelope_lighting.md, "Session 59").
  if (!feature.options().talk_light_grid) feature.options().talk_light_grid = true;
  RenderSessionDesc d;
  d.level = o.level;
  d.width = o.width, d.height = o.height;
  RenderSession session(d, run);
  render::ReferenceTracer tracer(session.ctx(), feature.pipeline_library());
  // One light alone (--cloud-lights sun|sky): the reference traces the same one (the lightning's point lights stay in both).
  const render::CloudLights lights = feature.options().lights;
  tracer.settings().sun = lights != render::CloudLights::Sky;
  tracer.settings().sky = lights != render::CloudLights::Sun;
  render::HdrCapture capture(session.ctx());
  const float level_tod = session.time_of_day();
  const uint32_t all_effects = feature.options().effects;
  std::vector<ViewResult> results;
  Stopwatch total;
  for (size_t vi = 0; vi < views.size(); ++vi) {
    const FidelityView& v = views[vi];
    std::fprintf(stderr, "cumulo fidelity: [%zu/%zu] %s\n", vi + 1, views.size(), v.name.c_str());
    ecs::Entity camera = session.camera(v.camera);
    session.set_time_of_day(v.time_of_day.value_or(level_tod));
    if (v.position) session.place_camera(camera, *v.position, *v.look_at, v.fov_y_deg);
    if (!v.sun.empty()) {
      const glm::vec3 sun = cumulo::render::extract_frame(session.sim().world(), camera, 1, 1).sun.direction;
      glm::vec2 h(sun.x, sun.z);
      h = glm::length(h) > 1e-4f ? glm::normalize(h) : glm::vec2(1.0f, 0.0f);
      const glm::vec2 at = glm::vec2(v.target.x, v.target.z) + h * (v.sun == "behind" ? -v.distance : v.distance);
      session.place_camera(camera, glm::vec3(at.x, v.height, at.y), v.target, v.fov_y_deg);
      std::fprintf(stderr, "cumulo fidelity: %s: sun toward (%.2f, %.2f, %.2f), camera at (%.0f, %.0f, %.0f)\n", v.name.c_str(),
                   sun.x, sun.y, sun.z, at.x, v.height, at.y);
    }
    if (!v.event.empty()) {
      app::fire_event(session.sim().world(), v.event);
      session.sim().step(std::max(1u, v.event_steps));
    }
    ViewResult r;
    r.view = v;
    const std::string base = (images / v.name).string();
    feature.options().effects = all_effects;
    // The real-time image with each set of constants; the first is the one the effect and the images use.
    std::vector<std::vector<glm::vec4>> rt_presets;
    std::vector<gpu::Rgba8Image> rt_preset_pngs;
    for (render::CloudLightingPreset p : o.presets) {
      feature.options().lighting = p;
      rt_presets.push_back(realtime_image(session, feature, capture, camera, o));
      rt_preset_pngs.push_back(session.screenshot());
    }
    feature.options().lighting = o.presets.front();
    const std::vector<glm::vec4>& rt = rt_presets.front();
    const gpu::Rgba8Image& rt_png = rt_preset_pngs.front();
    std::vector<glm::vec4> rt_off;
    gpu::Rgba8Image rt_off_png;
    if (!v.effect.empty()) {
      feature.options().effects = all_effects & ~render::cloud_effect_bit(v.effect);
      rt_off = realtime_image(session, feature, capture, camera, o);
      rt_off_png = session.screenshot();
      feature.options().effects = all_effects;
    }
    // The reference: traced, or with --reuse-references the one a previous run wrote at the same size and spp
    // (the tracer is deterministic: the same scene, settings and seed give the same image).
    render::ReferenceImage ref;
    gpu::Rgba8Image ref_png;
    if (!(o.reuse_references && load_reference(base, o, lights, ref, ref_png))) {
      feature.set_reference(&tracer);
      ref = accumulate_reference(session, tracer, camera, o.ref, v.name, &r.reference_seconds);
      feature.set_reference(nullptr);
      ref_png = session.screenshot();
      std::vector<glm::vec4> se(ref.radiance.size());
      for (size_t i = 0; i < se.size(); ++i)
        se[i] = glm::vec4(ref.luminance_stderr[i], float(ref.samples), float(ref.majorant_violations), lights_tag(lights));
      write_exr(base + "_reference_stderr.exr", ref.width, ref.height, se);
    } else {
      std::fprintf(stderr, "cumulo fidelity: %s: reusing %s_reference.exr (%u spp)\n", v.name.c_str(), base.c_str(), ref.samples);
      r.reference_reused = true;
    }
    r.spp = ref.samples;
    r.err = fidelity_error(rt, ref);
    const ReferenceFeatures ref_features = reference_features(ref);
    for (const std::vector<glm::vec4>& img : rt_presets) {
      r.preset_err.push_back(fidelity_error(img, ref));
      r.preset_features.push_back(view_features(img, ref, ref_features));
    }
    for (size_t k = 1; k < o.presets.size(); ++k) {
      const std::string name = render::lighting_preset_name(o.presets[k]);
      gpu::write_png(base + "_realtime_" + name + ".png", rt_preset_pngs[k]);
      gpu::write_png(base + "_error_" + name + ".png", error_map(rt_presets[k], ref));
    }
    const gpu::Rgba8Image err_png = error_map(rt, ref);
    if (!r.reference_reused) write_exr(base + "_reference.exr", ref.width, ref.height, ref.radiance);
    write_exr(base + "_realtime.exr", ref.width, ref.height, rt);
    gpu::write_png(base + "_realtime.png", rt_png);
    gpu::write_png(base + "_reference.png", ref_png);
    gpu::write_png(base + "_error.png", err_png);
    gpu::write_png(base + "_side_by_side.png", side_by_side({&rt_png, &ref_png, &err_png}));
    auto rel = [&](const std::string& p) { return fs::relative(p, fs::path(o.out).parent_path().empty() ? "." : fs::path(o.out).parent_path()).string(); };
    r.images = {{"realtime", rel(base + "_realtime.png")},       {"reference", rel(base + "_reference.png")},
                {"error", rel(base + "_error.png")},             {"side_by_side", rel(base + "_side_by_side.png")},
                {"reference_exr", rel(base + "_reference.exr")}, {"realtime_exr", rel(base + "_realtime.exr")}};
    for (size_t k = 1; k < o.presets.size(); ++k) {
      const std::string name = render::lighting_preset_name(o.presets[k]);
      r.images["realtime_" + name] = rel(base + "_realtime_" + name + ".png");
      r.images["error_" + name] = rel(base + "_error_" + name + ".png");
    }
    if (!v.effect.empty()) {
      r.err_off = fidelity_error(rt_off, ref);
      double c = 0;
      uint64_t n = 0;
      for (size_t i = 0; i < rt.size(); ++i)
        if (ref.radiance[i].a >= kCloudOpacity) {
          const double L = std::max(1e-4f, luminance(glm::vec3(ref.radiance[i])));
          c += std::fabs(luminance(glm::vec3(rt[i])) - luminance(glm::vec3(rt_off[i]))) / L;
          ++n;
        }
      r.effect_contribution = n ? c / double(n) : 0.0;
      const std::string off = base + "_realtime_without_" + v.effect;
      gpu::write_png(off + ".png", rt_off_png);
      const gpu::Rgba8Image err_off_png = error_map(rt_off, ref);
      gpu::write_png(base + "_error_without_" + v.effect + ".png", err_off_png);
      r.images["realtime_without_effect"] = rel(off + ".png");
      r.images["error_without_effect"] = rel(base + "_error_without_" + v.effect + ".png");
    }
    std::fprintf(stderr, "cumulo fidelity: %s: error %.1f %% (in cloud %.1f %%, noise-corrected %.1f %%, bias %+.1f %%, "
                 "reference noise %.1f %%; mean luminance in cloud: real-time %.3f, reference %.3f)%s\n",
                 v.name.c_str(), 100 * r.err.error_mean, 100 * r.err.error_in_cloud, 100 * r.err.error_in_cloud_corrected,
                 100 * r.err.bias_in_cloud, 100 * r.err.noise_in_cloud, r.err.realtime_luminance_in_cloud, r.err.reference_luminance_in_cloud,
                 v.effect.empty() ? "" : strf("; without %s %.1f %%", v.effect.c_str(), 100 * r.err_off.error_in_cloud).c_str());
    for (size_t k = 1; k < o.presets.size(); ++k)
      std::fprintf(stderr, "cumulo fidelity: %s: %s constants: error %.1f %%, in cloud %.1f %%, noise-corrected %.1f %% (bias %+.1f %%)\n",
                   v.name.c_str(), render::lighting_preset_name(o.presets[k]), 100 * r.preset_err[k].error_mean,
                   100 * r.preset_err[k].error_in_cloud, 100 * r.preset_err[k].error_in_cloud_corrected,
                   100 * r.preset_err[k].bias_in_cloud);
    for (size_t k = 0; k < o.presets.size(); ++k) {
      const ViewFeatures& f = r.preset_features[k];
      std::fprintf(stderr, "cumulo fidelity: %s: %s constants: belly %.3f vs %.3f, rim/core %.2f vs %.2f, band-pass %.3f vs %.3f "
                   "(real-time vs reference)\n", v.name.c_str(), render::lighting_preset_name(o.presets[k]), f.belly_realtime,
                   f.belly_reference, f.rim_core_realtime, f.rim_core_reference, f.band_pass_realtime, f.band_pass_reference);
    }
    results.push_back(r);
  }
  feature.options().effects = all_effects;

  // ---- Table and JSON ----
  auto pct = [](double v) { return std::isnan(v) ? std::string("-") : strf("%.1f %%", 100.0 * v); };
  const std::string first = render::lighting_preset_name(o.presets.front());
  std::string table = "| view | effect | error (all) | error in cloud, " + first + " constants | noise-corrected | bias in cloud |";
  std::string rule = "|---|---|---|---|---|---|";
  for (size_t k = 1; k < o.presets.size(); ++k) {
    table += strf(" error in cloud (noise-corrected), bias, %s constants |", render::lighting_preset_name(o.presets[k]));
    rule += "---|";
  }
  table += " reference noise | in cloud without the effect | effect's contribution | spp |\n" + rule + "---|---|---|---|\n";
  for (const ViewResult& r : results) {
    std::string extra;
    for (size_t k = 1; k < r.preset_err.size(); ++k)
      extra += strf(" %s (%s), %+.1f %% |", pct(r.preset_err[k].error_in_cloud).c_str(), pct(r.preset_err[k].error_in_cloud_corrected).c_str(),
                    100 * r.preset_err[k].bias_in_cloud);
    table += strf("| %s | %s | %s | %s | %s | %s |%s %s | %s | %s | %u |\n", r.view.name.c_str(),
                  r.view.effect.empty() ? "-" : r.view.effect.c_str(), pct(r.err.error_mean).c_str(), pct(r.err.error_in_cloud).c_str(),
                  pct(r.err.error_in_cloud_corrected).c_str(), strf("%+.1f %%", 100 * r.err.bias_in_cloud).c_str(), extra.c_str(), pct(r.err.noise_in_cloud).c_str(),
                  r.view.effect.empty() ? "-" : pct(r.err_off.error_in_cloud).c_str(),
                  r.view.effect.empty() ? "-" : pct(r.effect_contribution).c_str(), r.spp);
  }
  // What a viewer sees: the belly, the rim and the inside's structure, against the reference's (issue 21).
  table += "\n| view | constants | belly, lower third (real-time / reference) | rim / core (real-time / reference) | band-pass contrast (real-time / reference) |\n|---|---|---|---|---|\n";
  for (const ViewResult& r : results)
    for (size_t k = 0; k < r.preset_features.size(); ++k) {
      const ViewFeatures& f = r.preset_features[k];
      auto pair = [&](double a, double b, double d) { return strf("%.3f / %.3f (%s)", a, b, std::isnan(d) ? "-" : strf("%+.0f %%", 100 * d).c_str()); };
      table += strf("| %s | %s | %s | %s | %s |\n", r.view.name.c_str(), render::lighting_preset_name(o.presets[k]),
                    pair(f.belly_realtime, f.belly_reference, f.belly_difference()).c_str(),
                    pair(f.rim_core_realtime, f.rim_core_reference, f.rim_core_difference()).c_str(),
                    pair(f.band_pass_realtime, f.band_pass_reference, f.band_pass_difference()).c_str());
    }
  std::string preset_names;
  for (render::CloudLightingPreset p : o.presets) preset_names += std::string(preset_names.empty() ? "" : ", ") + render::lighting_preset_name(p);
  std::printf("## cumulo fidelity: %s, %ux%u, %u spp, %u bounces, phase %s, constants %s (%.0f s)\n\n%s\n",
              session.ctx().info().name.c_str(), o.width, o.height, o.ref.spp, o.ref.max_bounces,
              render::reference_phase_name(o.ref.phase), preset_names.c_str(), total.seconds(), table.c_str());

  nlohmann::ordered_json j;
  j["device"] = {{"name", session.ctx().info().name}, {"driver", session.ctx().info().driver_name},
                 {"driver_info", session.ctx().info().driver_info}};
  j["settings"] = {{"level", o.level},
                   {"views_file", views_file.string()},
                   {"size", {o.width, o.height}},
                   {"spp", o.ref.spp},
                   {"max_bounces", o.ref.max_bounces},
                   {"phase", render::reference_phase_name(o.ref.phase)},
                   {"seed", o.ref.seed},
                   {"realtime_warmup_frames", o.warmup},
                   {"realtime_frames_averaged", o.frames},
                   {"cloud_opacity_threshold", kCloudOpacity},
                   {"opaque_opacity_threshold", kOpaqueOpacity},
                   {"lights", name_of(render::kCloudLightsNames, lights)},
                   {"light_grid", light_grid_json(feature)},
                   {"constants", nlohmann::ordered_json::array()}};
  for (render::CloudLightingPreset p : o.presets) j["settings"]["constants"].push_back(render::lighting_preset_name(p));
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  auto num = [](double v) { return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v); };
  for (const ViewResult& r : results) {
    nlohmann::ordered_json e = {{"name", r.view.name},
                                {"error_mean", r.err.error_mean},
                                {"error_in_cloud", r.err.error_in_cloud},
                                {"error_in_cloud_noise_corrected", r.err.error_in_cloud_corrected},
                                {"bias_in_cloud", r.err.bias_in_cloud},
                                {"reference_noise_in_cloud", r.err.noise_in_cloud},
                                {"reference_stderr_in_cloud", r.err.stderr_in_cloud},
                                {"cloud_pixels", r.err.cloud_pixels},
                                {"realtime_luminance_in_cloud", r.err.realtime_luminance_in_cloud},
                                {"reference_luminance_in_cloud", r.err.reference_luminance_in_cloud},
                                {"spp", r.spp},
                                {"reference_seconds", r.reference_reused ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.reference_seconds)},
                                {"reference_reused", r.reference_reused},
                                {"images", r.images}};
    if (!r.view.note.empty()) e["note"] = r.view.note;
    nlohmann::ordered_json by = nlohmann::ordered_json::object();
    for (size_t k = 0; k < r.preset_err.size(); ++k) {
      const ViewFeatures& f = r.preset_features[k];
      by[render::lighting_preset_name(o.presets[k])] = {
          {"error_mean", r.preset_err[k].error_mean},
          {"error_in_cloud", r.preset_err[k].error_in_cloud},
          {"error_in_cloud_noise_corrected", r.preset_err[k].error_in_cloud_corrected},
          {"bias_in_cloud", r.preset_err[k].bias_in_cloud},
          {"error_opaque_noise_corrected", r.preset_err[k].error_opaque_corrected},
          {"bias_opaque", r.preset_err[k].bias_opaque},
          {"opaque_pixels", r.preset_err[k].opaque_pixels},
          {"belly_lower_third", {{"realtime", num(f.belly_realtime)}, {"reference", num(f.belly_reference)}, {"difference", num(f.belly_difference())}}},
          {"rim_core_ratio", {{"realtime", num(f.rim_core_realtime)}, {"reference", num(f.rim_core_reference)}, {"difference", num(f.rim_core_difference())}}},
          {"band_pass_contrast", {{"realtime", num(f.band_pass_realtime)}, {"reference", num(f.band_pass_reference)}, {"difference", num(f.band_pass_difference())}}}};
    }
    e["constants"] = by;
    if (!r.view.effect.empty())
      e["effect"] = {{"name", r.view.effect},
                     {"error_mean_without", r.err_off.error_mean},
                     {"error_in_cloud_without", r.err_off.error_in_cloud},
                     {"bias_in_cloud_without", r.err_off.bias_in_cloud},
                     {"contribution_in_cloud", num(r.effect_contribution)}};
    list.push_back(e);
  }
  j["views"] = list;
  write_file_atomic(o.out, j.dump(2) + "\n");
  std::printf("cumulo fidelity: wrote %s and the images in %s\n", o.out.c_str(), images.string().c_str());
  if (session.ctx().validation_errors() > 0) {
    std::fprintf(stderr, "cumulo fidelity: %u Vulkan validation errors (last: %s)\n", session.ctx().validation_errors(),
                 session.ctx().last_validation_message().c_str());
    return 3;
  }
  return 0;
}

}  // namespace

void register_fidelity_command(CommandRegistry& registry, const CloudsRun& run) {
  registry.add({"fidelity", "measure the real-time clouds against the path-traced reference, view by view (JSON + images)",
                [run](int argc, char** argv) {
                  FidelityOptions o;
                  std::string size, views, constants;
                  ArgParser p("cumulo fidelity",
                              "For each view of the level's fidelity set (fidelity.json beside the level: its cameras and\n"
                              "close-ups of each lighting effect of the talks), render the real-time image (still, averaged\n"
                              "over frames) and the path-traced reference, and report the mean relative luminance error over\n"
                              "the image and inside the cloud silhouette, with false-colour error maps. A view that names an\n"
                              "effect is rendered again with it off, to measure what it contributes.");
                  p.positional("LEVEL", "level.json (default the sample level)", &o.level, false)
                      .option("--views", "A,B", "only these views of the set", &views)
                      .option("--views-file", "FILE", "the view set (default: fidelity.json beside the level)", &o.views_file)
                      .option("--size", "WxH", "image size (default 160x90)", &size)
                      .option("--frames", "N", "real-time frames averaged per view (default 24)", &o.frames)
                      .option("--warmup", "N", "real-time frames before averaging (default 8)", &o.warmup)
                      .option("--out", "FILE.json", "results (default fidelity.json)", &o.out)
                      .option("--images", "DIR", "image folder (default: FILE_images beside --out)", &o.images)
                      .flag("--reuse-references", "take each view's reference from the image folder when a previous run "
                            "wrote it at this size and spp (to compare other real-time settings without re-tracing)",
                            &o.reuse_references)
                      .option("--constants", "A,B", "real-time lighting constants compared, the first also for the effects "
                              "and images (default slab,talk: the default lighting and the talks' side by side)", &constants);
                  add_reference_options(p, o.ref);
                  run.add_run_options(p);  // --cloud-* (the real-time side's switches)
                  if (!p.parse(argc, argv)) return 0;
                  check_reference_options(o.ref);
                  if (!size.empty()) app::parse_size(size, o.width, o.height);
                  if (o.frames < 1 || o.frames > 1000) fail("--frames: %u is outside 1..1000", o.frames);
                  if (o.warmup > 1000) fail("--warmup: %u is outside 0..1000", o.warmup);
                  if (!constants.empty()) {
                    o.presets.clear();
                    std::stringstream cs(constants);
                    for (std::string item; std::getline(cs, item, ',');) {
                      o.presets.push_back(parse_name_or_fail(render::kCloudLightingPresetNames, "--constants", item));
                    }
                    if (o.presets.empty()) fail("--constants: none named");
                  }
                  std::stringstream ss(views);
                  for (std::string item; std::getline(ss, item, ',');)
                    if (!item.empty()) o.only.push_back(item);
                  return run_fidelity(o, run);
                }});
}

}  // namespace cumulo::clouds
