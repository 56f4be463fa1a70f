#include "modules/clouds/bake/grow/grown_cloud.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "engine/core/memory_budget.h"
#include "engine/core/parallel.h"
#include "engine/core/png.h"
#include "engine/core/progress.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds::grow {

namespace {

constexpr int kCropMargin = 2;  // cells of clear air kept around the cloud (the SDF's outside band)
constexpr float kMinPieceShare = 0.02f;

size_t remove_small_pieces(std::vector<float>& qc, glm::ivec3 n, float iso) {
  const size_t count = qc.size();
  std::vector<int> label(count, -1);
  std::vector<size_t> sizes;
  std::vector<size_t> stack;
  const size_t sy = size_t(n.x), sz = size_t(n.x) * n.y;
  for (size_t c0 = 0; c0 < count; ++c0) {
    if (label[c0] >= 0 || !(qc[c0] > iso)) continue;
    const int id = int(sizes.size());
    size_t size = 0;
    stack.push_back(c0);
    label[c0] = id;
    while (!stack.empty()) {
      const size_t c = stack.back();
      stack.pop_back();
      ++size;
      const int x = int(c % sy), y = int((c / sy) % n.y), z = int(c / sz);
      const size_t nb[6] = {x > 0 ? c - 1 : c, x + 1 < n.x ? c + 1 : c, y > 0 ? c - sy : c,
                            y + 1 < n.y ? c + sy : c, z > 0 ? c - sz : c, z + 1 < n.z ? c + sz : c};
      for (size_t q : nb)
        if (label[q] < 0 && qc[q] > iso) label[q] = id, stack.push_back(q);
    }
    sizes.push_back(size);
  }
  size_t largest = 0;
  for (size_t s : sizes) largest = std::max(largest, s);
  const size_t keep = std::max<size_t>(8, size_t(kMinPieceShare * float(largest)));
  size_t removed = 0;
  for (size_t c = 0; c < count; ++c)
    if (label[c] >= 0 && sizes[label[c]] < keep) qc[c] = 0.0f, ++removed;
  return removed;
}

float max_abs(const std::vector<float>& v) {
  float m = 0.0f;
  for (float a : v) m = std::max(m, std::abs(a));
  return m;
}

}  // namespace

GrownCloud grow_cloud(const GrowSpec& spec, GrowReport* report, Progress* progress) {
  const glm::ivec3 n = spec.solver.dims;
  // Solver fields (u, v, w, theta, qv, qc, condensation, pressure, two scratch traces of vec3, three
  // advection scratch fields, force/vorticity scratch of 3 x vec3) and the multigrid/CG vectors:
  // about 56 floats per cell at the peak.
  constexpr uint64_t kBytesPerCell = 56 * 4;
  check_memory_budget(saturating_product({uint64_t(n.x), uint64_t(n.y), uint64_t(n.z), kBytesPerCell}),
                      strf("%s: a grow grid of %dx%dx%d cells ($.grid.cells)", spec.file.c_str(), n.x, n.y, n.z));
  Stopwatch clock;
  CloudSolver solver(spec.solver);
  long cg_total = 0;
  float max_w = 0.0f;
  for (int s = 0; s < spec.steps; ++s) {
    solver.step();
    cg_total += solver.last_pressure_iterations();
    if (progress) progress->add(1.0);
    if (!std::isfinite(solver.max_velocity()) || solver.max_velocity() > 500.0f)
      fail("%s: the simulation became unstable at step %d (a velocity of %g m/s): lower $.time.dt or the thermals' heat",
           spec.file.c_str(), s + 1, solver.max_velocity());
  }
  for (float w : solver.vertical_velocity()) max_w = std::max(max_w, w);

  // Speckle: single cells that a gravity wave lifted past saturation are not part of the cloud. Keep
  // the 6-connected pieces of at least kMinPieceShare of the largest one (and 8 cells).
  std::vector<float> qc = solver.cloud_water();
  const size_t removed = remove_small_pieces(qc, n, spec.iso);
  // Crop to the cells above the iso-surface plus a margin.
  glm::ivec3 lo(INT32_MAX), hi(INT32_MIN);
  uint64_t cloud_cells = 0;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        if (qc[solver.index(i, j, k)] > spec.iso) {
          lo = glm::min(lo, glm::ivec3(i, j, k)), hi = glm::max(hi, glm::ivec3(i, j, k));
          ++cloud_cells;
        }
  if (cloud_cells == 0)
    fail("%s: no cloud grew (no cloud water above $.output.iso = %g g/kg after %d steps): add heat or moisture to the "
         "thermals, lower the lapse-rate stability, or run longer",
         spec.file.c_str(), spec.iso * 1e3f, spec.steps);
  const glm::ivec3 base_cell = lo;
  // Placement is by the cloud, not by the solver's box (shear carries a cloud downwind of its thermal).
  const glm::vec2 cloud_centre_xz(0.5f * float(lo.x + hi.x + 1), 0.5f * float(lo.z + hi.z + 1));
  lo = glm::max(lo - kCropMargin, glm::ivec3(0));
  hi = glm::min(hi + kCropMargin, n - 1);

  GrownCloud g;
  g.dims = glm::uvec3(hi - lo + 1);
  g.cell = spec.cell_game;
  g.iso = spec.iso;
  // Local frame: the cloud's x/z centre (of its cells above the iso), cloud base at y = 0 (the base cell's lower face).
  const glm::vec3 centre(cloud_centre_xz.x, float(base_cell.y), cloud_centre_xz.y);
  g.origin = (glm::vec3(lo) + 0.5f - centre) * g.cell;
  const std::vector<float> w = solver.vertical_velocity();
  const std::vector<float>& cond = solver.condensation();
  const std::vector<float>& growth = solver.growth();
  const size_t count = g.count();
  g.cloud_water.resize(count), g.condensation.resize(count), g.vertical_velocity.resize(count), g.growth.resize(count);
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) {
        const size_t src = solver.index(lo.x + int(i), lo.y + int(j), lo.z + int(k)), dst = g.index(i, j, k);
        g.cloud_water[dst] = qc[src];
        g.condensation[dst] = cond[src];
        g.vertical_velocity[dst] = w[src];
        g.growth[dst] = growth[src];
      }

  if (report) {
    GrowReport& r = *report;
    r.steps = spec.steps;
    r.physical_seconds = solver.time();
    r.wall_seconds = clock.seconds();
    r.threads = worker_count();
    r.water = solver.budget();
    r.total_water_drift = r.water.advection_residual / std::max(r.water.initial, 1e-30);
    r.cloud_base_m = float(base_cell.y) * g.cell;
    r.cloud_top_m = float(hi.y - kCropMargin + 1) * g.cell;
    r.condensation_level_m = solver.atmosphere().condensation_level() / spec.scale;
    r.cloud_size = glm::vec3(hi - lo + 1 - 2 * kCropMargin) * g.cell;
    r.cloud_cells = cloud_cells;
    r.speckle_cells_removed = removed;
    r.max_cloud_water = *std::max_element(qc.begin(), qc.end());
    r.max_updraft = max_w;
    r.mean_pressure_iterations = int(cg_total / std::max(1, spec.steps));
  }
  return g;
}

Volume grown_to_volume(const GrownCloud& g) {
  auto range = [](const std::vector<float>& v, bool is_signed) {
    const float m = std::max(max_abs(v), 1e-12f);
    return is_signed ? glm::vec2(-m, m) : glm::vec2(0.0f, m);
  };
  const glm::vec2 rq = range(g.cloud_water, false), rc = range(g.condensation, true), rw = range(g.vertical_velocity, true),
                  rt = range(g.growth, true);
  Volume v = Volume::create(g.dims, g.cell, VolumeEncoding::RGBA16,
                            {{"qc", std::string(kCloudWater), rq.x, rq.y},
                             {"condensation", std::string(kCondensation), rc.x, rc.y},
                             {"w", std::string(kVerticalVelocity), rw.x, rw.y},
                             {"growth", std::string(kGrowth), rt.x, rt.y}});
  v.bounds_min = g.bounds_min();
  v.bounds_max = g.bounds_max();
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) {
        const size_t c = g.index(i, j, k);
        v.set_decoded(i, j, k, 0, g.cloud_water[c]);
        v.set_decoded(i, j, k, 1, g.condensation[c]);
        v.set_decoded(i, j, k, 2, g.vertical_velocity[c]);
        v.set_decoded(i, j, k, 3, g.growth[c]);
      }
  return v;
}

GrownCloud grown_from_volume(const Volume& v, const std::string& what) {
  GrownCloud g;
  g.dims = v.size;
  g.cell = v.voxel_size;
  g.origin = v.bounds_min + 0.5f * g.cell;
  const uint32_t cq = v.channel(kCloudWater, what), cc = v.channel(kCondensation, what),
                 cw = v.channel(kVerticalVelocity, what), cg = v.channel(kGrowth, what);
  const size_t n = g.count();
  g.cloud_water.resize(n), g.condensation.resize(n), g.vertical_velocity.resize(n), g.growth.resize(n);
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) {
        const size_t c = g.index(i, j, k);
        g.cloud_water[c] = v.decoded(i, j, k, cq);
        g.condensation[c] = v.decoded(i, j, k, cc);
        g.vertical_velocity[c] = v.decoded(i, j, k, cw);
        g.growth[c] = v.decoded(i, j, k, cg);
      }
  return g;
}

void save_grown(const std::filesystem::path& path, const GrownCloud& g) { save_volume(path, grown_to_volume(g)); }

GrownCloud load_grown(const std::filesystem::path& path) {
  Volume v = load_volume(path);
  GrownCloud g = grown_from_volume(v, path.string());
  return g;
}

namespace {

// Vertical section through the box centre (x by y) beside a horizontal one at 40 % of the cloud's
// height (x by z): cloud water as brightness, condensation as colour (warm condensing, blue evaporating).
std::vector<uint8_t> section_image(const GrownCloud& g, uint32_t* w_out, uint32_t* h_out) {
  const uint32_t W = g.dims.x * 2 + 4, H = std::max(g.dims.y, g.dims.z);
  std::vector<uint8_t> img(size_t(W) * H * 3, 0);
  const float qmax = std::max(max_abs(g.cloud_water), 1e-12f), cmax = std::max(max_abs(g.condensation), 1e-12f);
  auto put = [&](uint32_t x, uint32_t y, size_t c) {
    const float q = std::sqrt(g.cloud_water[c] / qmax), k = g.condensation[c] / cmax;
    uint8_t* p = &img[(size_t(y) * W + x) * 3];
    p[0] = uint8_t(std::clamp(255.0f * (q + 0.5f * std::max(k, 0.0f)), 0.0f, 255.0f));
    p[1] = uint8_t(std::clamp(255.0f * q, 0.0f, 255.0f));
    p[2] = uint8_t(std::clamp(255.0f * (q + 0.5f * std::max(-k, 0.0f)), 0.0f, 255.0f));
  };
  const uint32_t kz = g.dims.z / 2, jy = uint32_t(0.4f * g.dims.y);
  for (uint32_t j = 0; j < g.dims.y; ++j)
    for (uint32_t i = 0; i < g.dims.x; ++i) put(i, g.dims.y - 1 - j, g.index(i, j, kz));
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t i = 0; i < g.dims.x; ++i) put(g.dims.x + 4 + i, k, g.index(i, jy, k));
  *w_out = W, *h_out = H;
  return img;
}

}  // namespace

std::string recorded_grow_key(const std::filesystem::path& dir) {
  std::error_code ec;
  const auto report = dir / "grow_report.json";
  if (!std::filesystem::is_regular_file(report, ec)) return "";
  try {
    const auto j = nlohmann::json::parse(read_file_text(report));
    return j.value("key", std::string());
  } catch (const std::exception&) {
    return "";
  }
}

std::string write_grow_outputs(const GrowSpec& spec, const GrownCloud& g, const GrowReport& r,
                               const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail("%s: cannot create the output folder: %s", dir.string().c_str(), ec.message().c_str());
  FileSet files;
  const std::vector<uint8_t> bytes = serialize_volume(grown_to_volume(g));
  files.add(dir / "grown.nvdf", bytes);

  nlohmann::ordered_json rep;
  rep["spec"] = spec.file;
  rep["preset"] = spec.preset;
  rep["key"] = grow_key_hex(spec);
  rep["solver_version"] = kSolverVersion;
  rep["axes"] = "texel (i, j, k) = local (x, y up, z) game metres; y = 0 at the cloud base, x/z centred on the cloud";
  rep["grid"] = {{"cells", {spec.solver.dims.x, spec.solver.dims.y, spec.solver.dims.z}},
                 {"cell_m", spec.cell_game},
                 {"physical_cell_m", spec.solver.cell},
                 {"scale", spec.scale}};
  rep["output_dims"] = {g.dims.x, g.dims.y, g.dims.z};
  rep["bounds"] = {{"min", {g.bounds_min().x, g.bounds_min().y, g.bounds_min().z}},
                   {"max", {g.bounds_max().x, g.bounds_max().y, g.bounds_max().z}}};
  rep["steps"] = r.steps;
  rep["dt_s"] = spec.solver.dt;
  rep["physical_time_s"] = r.physical_seconds;
  rep["wall_time_s"] = r.wall_seconds;
  rep["threads"] = r.threads;
  rep["mean_pressure_iterations"] = r.mean_pressure_iterations;
  rep["cloud"] = {{"base_m", r.cloud_base_m},
                  {"top_m", r.cloud_top_m},
                  {"condensation_level_m", r.condensation_level_m},
                  {"size_m", {r.cloud_size.x, r.cloud_size.y, r.cloud_size.z}},
                  {"cells_above_iso", r.cloud_cells},
                  {"speckle_cells_removed", r.speckle_cells_removed},
                  {"iso_g_per_kg", spec.iso * 1e3},
                  {"max_cloud_water_g_per_kg", r.max_cloud_water * 1e3},
                  {"max_updraft_m_per_s", r.max_updraft}};
  rep["water_budget"] = {{"unit", "kg/kg summed over cells (vapour + cloud water)"},
                         {"initial", r.water.initial},
                         {"sourced", r.water.sourced},
                         {"dried", r.water.dried},
                         {"final", r.water.final_total},
                         {"final_cloud_water", r.water.final_cloud_water},
                         {"advection_residual", r.water.advection_residual},
                         {"drift_of_initial", r.total_water_drift}};
  rep["files"] = {{"grown.nvdf", bytes.size()}};
  uint32_t w = 0, h = 0;
  const std::vector<uint8_t> img = section_image(g, &w, &h);
  const std::filesystem::path png_tmp = dir / ".grown_section.png.tmp";
  write_png(png_tmp, img.data(), w, h, 3);
  files.add(dir / "grown_section.png", read_file_bytes(png_tmp));
  std::filesystem::remove(png_tmp, ec);
  const std::filesystem::path vdb_tmp = dir / ".grown.vdb.tmp";
  if (write_grown_vdb(vdb_tmp, g)) {
    files.add(dir / "grown.vdb", read_file_bytes(vdb_tmp));
    std::filesystem::remove(vdb_tmp, ec);
    rep["files"]["grown.vdb"] = "OpenVDB FloatGrid \"density\" (fog volume: cloud water over the iso, 0..1)";
  }
  const std::string text = rep.dump(2) + "\n";
  files.add(dir / "grow_report.json", text);
  files.commit();
  return text;
}

}  // namespace cumulo::clouds::grow
