#include "modules/clouds/bake/bake.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "engine/core/error.h"
#include "engine/core/memory_budget.h"
#include "engine/core/file_io.h"
#include "engine/core/parallel.h"
#include "engine/core/progress.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::bake {

namespace {

// Stage progress: a Progress on a terminal, nothing otherwise.
struct Stage {
  std::optional<Progress> p;
  Stage(bool show, const std::string& label, double total) {
    if (show && Progress::terminal()) p.emplace(label, total);
  }
  Progress* get() { return p ? &*p : nullptr; }
  void add(double a) {
    if (p) p->add(a);
  }
  ~Stage() {
    if (p) p->finish();
  }
};

constexpr uint64_t kTalkBytes512 = 25165824;   // 2023 talk: voxel method, per cloudscape
constexpr uint64_t kBudgetBytes512 = 25200000;  // target for our GPU formats

}  // namespace

uint64_t bake_gpu_bytes(const char* format, glm::uvec3 dims) {
  VolumeEncoding e;
  if (!parse_encoding(format, &e)) fail("bake: unknown format %s", format);
  return encoded_level_bytes(e, dims);
}

namespace {

// The fair-weather field (volume/nvdf.h): the exact EDT of the inside voxels whose threshold is below the band,
// then the minimum of each 2x2x2 block less a margin that keeps the trilinear half-resolution field at or below
// the true distance everywhere: a block's voxel centres lie within sqrt(3) / 2 voxels of its texel centre, and a
// sample within sqrt(3) half-resolution texels (2 voxels) of each of the 8 it interpolates.
void build_fair_field(BakeResult& r) {
  const BakeGrid& g = r.grid;
  const size_t n = g.count();
  const float band = float(CLOUD_COVERAGE_BAND);
  bool banded = false;
  for (size_t i = 0; i < n && !banded; ++i) banded = r.field[i] < 0.0f && r.coverage[i] >= band;
  if (!banded) return;
  std::vector<uint8_t> inside(n);
  for (size_t i = 0; i < n; ++i) inside[i] = r.field[i] < 0.0f && r.coverage[i] < band;
  const float vs = g.spacing.x;
  const std::vector<float> sd = signed_distance_from_mask(inside, g.dims, vs);
  const glm::uvec3 hd = glm::max((g.dims + 1u) / 2u, glm::uvec3(1));
  const float margin = std::sqrt(3.0f) * 2.5f * vs;
  r.field_fair_dims = hd;
  r.field_fair16.resize(size_t(hd.x) * hd.y * hd.z);
  parallel_for(hd.z, [&](size_t b, size_t e) {
    for (size_t z = b; z < e; ++z)
      for (uint32_t y = 0; y < hd.y; ++y)
        for (uint32_t x = 0; x < hd.x; ++x) {
          float m = kFieldMax;
          for (uint32_t k = 0; k < 8; ++k) {
            const glm::uvec3 p = glm::min(glm::uvec3(2 * x + (k & 1), 2 * y + ((k >> 1) & 1), 2 * uint32_t(z) + (k >> 2)),
                                          g.dims - 1u);
            m = std::min(m, sd[g.index(p.x, p.y, p.z)]);
          }
          r.field_fair16[x + size_t(hd.x) * (y + size_t(hd.y) * z)] =
              field_to_unorm16(std::clamp(m - margin, kFieldMin, kFieldMax));
        }
  });
}

}  // namespace

BakeResult bake_recipe(const Recipe& input, const BakeSettings& settings) {
  Stopwatch total;
  Recipe recipe = input;
  if (settings.voxel_size > 0.0f) recipe.voxel_size = settings.voxel_size;
  BakeResult r;
  r.grid = make_grid(recipe, settings.dims);
  const BakeGrid& g = r.grid;
  {
    // Peak bytes per voxel, counted from the buffers below: composed sdf/detail/density/profile depth (16), field
    // and its EDT scratch (4 + 8), field16 (2), modeling floats (12), BC1 blocks (1), the serialized
    // RGBA8 + R16 files and their zstd copies (12), rounded up.
    constexpr uint64_t kBakeBytesPerVoxel = 60;
    const std::string source = settings.dims.x ? "--dims"
                               : settings.voxel_size > 0.0f ? strf("--voxel-size %g", settings.voxel_size)
                                                            : strf("$.voxel_size %g", recipe.voxel_size);
    // The coverage threshold: composed (4) and clamped (4); its half-resolution R8 file is a rounding error. The
    // fair-weather field: its mask (1), signed distance (4) and EDT scratch (8); its half-resolution R16 is small.
    constexpr uint64_t kCoverageBytesPerVoxel = 8 + 13;
    check_memory_budget(saturating_product({g.dims.x, g.dims.y, g.dims.z, kBakeBytesPerVoxel + kCoverageBytesPerVoxel}),
                        strf("%s: a bake grid of %ux%ux%u voxels (%s)", recipe.file.c_str(), g.dims.x, g.dims.y,
                             g.dims.z, source.c_str()));
  }
  finalize_edits(recipe, 3.0f * std::max(g.spacing.x, std::max(g.spacing.y, g.spacing.z)));
  const size_t n = g.count();

  Stopwatch sw;
  Composed composed;
  {
    Stage st(settings.show_progress, "bake: compose edits", double(g.dims.y) * g.dims.z);
    composed = compose(recipe, g, st.get());
  }
  r.edit_evaluations = composed.edit_evaluations;
  r.timings.compose = sw.seconds();

  sw.reset();
  {
    Stage st(settings.show_progress, "bake: distance field (exact EDT)", 4.0);
    r.field = build_field(composed.sdf, g, &r.field_stats, st.get());
    r.field16.resize(n);
    std::vector<double> row_err(g.dims.z, 0.0);
    parallel_for(g.dims.z, [&](size_t b, size_t e) {
      for (size_t z = b; z < e; ++z) {
        size_t base = z * size_t(g.dims.x) * g.dims.y;
        for (size_t i = base; i < base + size_t(g.dims.x) * g.dims.y; ++i) {
          r.field16[i] = field_to_unorm16(r.field[i]);
          row_err[z] = std::max(row_err[z], double(r.field[i]) - double(unorm16_to_field(r.field16[i])));
        }
      }
    });
    for (double e : row_err) r.field16_max_error_m = std::max(r.field16_max_error_m, e);
    st.add(1.0);
  }
  r.timings.field = sw.seconds();

  sw.reset();
  r.modeling.resize(n * 3);
  parallel_for(n, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      // Each voxel's own ramp depth: the recipe's, or a grown cloud's local-thickness depth.
      r.modeling[3 * i + 0] = profile_from_field(r.field[i], {composed.profile_depth[i], recipe.profile.exponent});
      r.modeling[3 * i + 1] = std::clamp(composed.detail_type[i], 0.0f, 1.0f);
      r.modeling[3 * i + 2] = std::clamp(composed.density_scale[i], 0.0f, 1.0f);
    }
  }, 4096);
  r.coverage.resize(n);
  for (size_t i = 0; i < n; ++i) r.coverage[i] = std::clamp(composed.coverage[i], 0.0f, 1.0f);
  r.timings.modeling = sw.seconds();
  build_fair_field(r);

  sw.reset();
  {
    const double blocks = double((g.dims.x + 3) / 4) * ((g.dims.y + 3) / 4) * g.dims.z;
    Stage st(settings.show_progress, "bake: BC1 field (conservative)", blocks);
    r.field_bc1 = encode_sdf_bc1(r.field16, g.dims, st.get());
  }
  r.timings.bc1_field = sw.seconds();

  sw.reset();
  {
    const double blocks = double((g.dims.x + 3) / 4) * ((g.dims.y + 3) / 4) * g.dims.z;
    Stage st(settings.show_progress, "bake: BC1 modeling", blocks);
    // The profile drives both the cloud/no-cloud test and the up-rez: weigh its error most.
    r.modeling_bc1 = encode_rgb_bc1(r.modeling, g.dims, glm::vec3(2.0f, 1.0f, 1.0f), st.get());
  }
  r.timings.bc1_modeling = sw.seconds();

  if (settings.verify) {
    sw.reset();
    Stage st(settings.show_progress, "bake: verify BC1", 1.0);
    r.field_bc1_report = verify_sdf_bc1(r.field_bc1, r.field16, g.dims, &r.field);
    r.modeling_bc1_report = measure_rgb_bc1(r.modeling_bc1, r.modeling, g.dims);
    if (r.field_bc1_report.violations || r.field_bc1_report.midpoint_violations)
      fail("%s: BC1 field is not conservative: %llu texels and %llu filtered points decode above the distance",
           recipe.file.c_str(), (unsigned long long)r.field_bc1_report.violations,
           (unsigned long long)r.field_bc1_report.midpoint_violations);
    st.add(1.0);
    r.timings.verify = sw.seconds();
  }
  r.timings.total = total.seconds();
  return r;
}

std::string write_bake_outputs(const Recipe& recipe, const BakeResult& r, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail("%s: cannot create the output folder: %s", dir.string().c_str(), ec.message().c_str());
  const BakeGrid& g = r.grid;
  const glm::uvec3 dims = g.dims;
  const glm::vec3 bmin = g.bounds_min(), bmax = g.bounds_max();
  const size_t n = g.count();

  auto place = [&](Volume v) {
    v.voxel_size = g.spacing.x;
    v.bounds_min = bmin;
    v.bounds_max = bmax;
    return v;
  };
  Volume modeling = place(make_modeling_volume(dims, g.spacing.x, bmin));
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      modeling.levels[0][4 * i + c] = static_cast<uint8_t>(std::lround(std::clamp(r.modeling[3 * i + c], 0.0f, 1.0f) * 255.0f));
  for (size_t i = 0; i < n; ++i) modeling.levels[0][4 * i + 3] = static_cast<uint8_t>(std::lround(r.coverage[i] * 255.0f));
  // The BC1 path's coverage thresholds (BC1 has three channels): the alpha, box-filtered to half resolution.
  Volume coverage = coverage_from_modeling(modeling);
  Volume modeling_bc1 = place(Volume::create(dims, g.spacing.x, VolumeEncoding::BC1,
                                             {{"r", std::string(kDimensionalProfile)},
                                              {"g", std::string(kDetailType)},
                                              {"b", std::string(kDensityScale)}}));
  modeling_bc1.levels[0] = r.modeling_bc1;
  Volume field = place(make_field_volume(dims, g.spacing.x, bmin));
  for (size_t i = 0; i < n; ++i) {
    field.levels[0][2 * i] = r.field16[i] & 0xFF;
    field.levels[0][2 * i + 1] = r.field16[i] >> 8;
  }
  // The BC1 field's three channels only mean something together: "sdf" names the packed R channel,
  // and the unpack weights are documented in bc1.h (kSdfUnpackDot).
  Volume field_bc1 = place(Volume::create(dims, g.spacing.x, VolumeEncoding::BC1,
                                          {{"sdf_hi5", std::string(kSignedDistance), kFieldMin, kFieldMax}}));
  field_bc1.levels[0] = r.field_bc1;

  struct Out {
    const char* file;
    const Volume* v;
    const char* format;
    const char* purpose;
    glm::uvec3 dims;
  };
  Volume field_fair;
  if (!r.field_fair16.empty()) {
    field_fair = place(make_field_volume(r.field_fair_dims, 2.0f * g.spacing.x, bmin));
    field_fair.voxel_size = 2.0f * g.spacing.x;
    for (size_t i = 0; i < r.field_fair16.size(); ++i) {
      field_fair.levels[0][2 * i] = r.field_fair16[i] & 0xFF;
      field_fair.levels[0][2 * i + 1] = r.field_fair16[i] >> 8;
    }
  }
  std::vector<Out> outs = {{"modeling.nvdf", &modeling, "rgba8", "modeling NVDF, uncompressed (CPU devices)", dims},
                      {"modeling_bc1.nvdf", &modeling_bc1, "bc1", "modeling NVDF, BC1 (GPUs)", dims},
                      {"coverage.nvdf", &coverage, "r8", "coverage thresholds at half resolution (the BC1 path)",
                       coverage.size},
                      {"field.nvdf", &field, "r16", "field NVDF, 16-bit SDF", dims},
                      {"field_bc1.nvdf", &field_bc1, "bc1", "field NVDF, conservative BC1 SDF", dims}};
  if (!r.field_fair16.empty())
    outs.push_back({"field_fair.nvdf", &field_fair, "r16",
                    "fair-weather field: SDF of the clouds below the coverage band, half resolution (both paths)",
                    r.field_fair_dims});
  // One set: a failed write (of any file, the report included) leaves the previous bake untouched.
  FileSet files;
  nlohmann::ordered_json outputs = nlohmann::ordered_json::array();
  for (const Out& o : outs) {
    std::vector<uint8_t> bytes = serialize_volume(*o.v);
    files.add(dir / o.file, bytes);
    outputs.push_back({{"file", o.file},
                       {"format", o.format},
                       {"purpose", o.purpose},
                       {"gpu_bytes", bake_gpu_bytes(o.format, o.dims)},
                       {"file_bytes", bytes.size()}});
  }

  const uint64_t fair_bytes = r.field_fair16.empty() ? 0 : bake_gpu_bytes("r16", r.field_fair_dims);
  const uint64_t compressed = bake_gpu_bytes("bc1", dims) * 2 + bake_gpu_bytes("r8", coverage.size) + fair_bytes;
  const uint64_t uncompressed = bake_gpu_bytes("rgba8", dims) + bake_gpu_bytes("r16", dims) + fair_bytes;
  const glm::uvec3 ref(512, 64, 512);
  nlohmann::ordered_json rep;
  rep["recipe"] = recipe.file;
  rep["name"] = recipe.name;
  rep["seed"] = recipe.seed;
  rep["axes"] = "texel (i, j, k) = world (x, y up, z); z slices are vertical layers";
  rep["dims"] = {dims.x, dims.y, dims.z};
  rep["voxel_size_m"] = {g.spacing.x, g.spacing.y, g.spacing.z};
  rep["bounds"] = {{"min", {bmin.x, bmin.y, bmin.z}}, {"max", {bmax.x, bmax.y, bmax.z}}};
  rep["voxels"] = n;
  rep["edits"] = recipe.edits.size();
  rep["edit_evaluations"] = r.edit_evaluations;
  rep["inside_voxels"] = r.field_stats.inside_voxels;
  rep["surface_voxels"] = r.field_stats.surface_voxels;
  rep["outputs"] = outputs;
  rep["gpu_memory"] = {
      {"compressed_path_bytes", compressed},
      {"compressed_path", "modeling_bc1 + coverage + field_bc1 (+ field_fair)"},
      {"uncompressed_path_bytes", uncompressed},
      {"uncompressed_path", "modeling (rgba8) + field (r16) (+ field_fair)"},
      {"compressed_path_bytes_at_512x64x512", bake_gpu_bytes("bc1", ref) * 2 + bake_gpu_bytes("r8", coverage_nvdf_size(ref))},
      {"talk_bytes_at_512x64x512", kTalkBytes512},
      {"budget_bytes_at_512x64x512", kBudgetBytes512}};
  const Bc1SdfReport& f = r.field_bc1_report;
  rep["field_bc1"] = {{"unpack_dot", {1.0, kSdfDotG, kSdfDotB}},
                      {"texels", f.texels},
                      {"violations", f.violations},
                      {"filtered_points_checked", f.midpoint_checks},
                      {"filtered_violations", f.midpoint_violations},
                      {"mean_error_vs_r16_m", f.mean_error_m},
                      {"max_error_vs_r16_m", f.max_error_m},
                      {"mean_error_vs_float_m", f.mean_error_vs_float_m},
                      {"max_error_vs_float_m", f.max_error_vs_float_m}};
  rep["field_r16"] = {{"max_error_vs_float_m", r.field16_max_error_m}, {"rounding", "down"}};
  const Bc1RgbReport& m = r.modeling_bc1_report;
  rep["modeling_bc1"] = {{"rmse", {m.rmse.x, m.rmse.y, m.rmse.z}}, {"max_error", {m.max_error.x, m.max_error.y, m.max_error.z}},
                         {"channels", {"dimensional_profile", "detail_type", "density_scale"}}};
  const BakeTimings& t = r.timings;
  rep["timings_s"] = {{"compose", t.compose},     {"field", t.field},   {"modeling", t.modeling},
                      {"bc1_field", t.bc1_field}, {"bc1_modeling", t.bc1_modeling}, {"verify", t.verify},
                      {"total", t.total},          {"threads", worker_count()}};
  std::string text = rep.dump(2) + "\n";
  files.add(dir / "bake_report.json", text);
  files.commit();
  return text;
}

}  // namespace cumulo::clouds::bake
