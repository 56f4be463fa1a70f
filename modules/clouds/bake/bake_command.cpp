#include "modules/clouds/bake/bake_command.h"

#include <cstdio>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/message.h"
#include "engine/core/parallel.h"
#include "modules/clouds/bake/bake.h"
#include "modules/clouds/volume/nvdf.h"

namespace cumulo::clouds {

namespace {

glm::uvec3 parse_dims(const std::string& s) {
  std::vector<uint32_t> d = parse_flag_list<uint32_t>("--dims", s, 3);
  for (uint32_t n : d)
    if (n == 0 || n > 4096) fail("--dims: expected X,Y,Z (1..4096 each, world axes with Y up), got %s", quote(s).c_str());
  return {d[0], d[1], d[2]};
}

double mb(uint64_t bytes) { return bytes / 1.0e6; }

}  // namespace

int run_bake_command(int argc, char** argv) {
  std::string recipe_path, out_dir, slices_dir;
  uint64_t seed = 0;
  float voxel = 0.0f;
  glm::uvec3 dims(0);
  bool no_verify = false;
  std::string grown_attributes = "simulated";
  ArgParser p("cumulo bake", "Bake a cloudscape recipe (JSON edit list) into modeling and field NVDFs.");
  p.positional("RECIPE", "cloudscape recipe (.json), e.g. content/levels/sample/cloudscape.json", &recipe_path)
      .option("-o", "DIR", "output folder (modeling*.nvdf, field*.nvdf, bake_report.json)", &out_dir)
      .option("--slices", "DIR", "also write PNG cross-sections of the profile and the SDF here", &slices_dir)
      .option("--seed", "N", "override the recipe's seed (particles, erosion noise)", &seed)
      .option("--voxel-size", "M", "override the recipe's voxel size in metres", &voxel)
      .range(0.0, 1024.0, Open::Low)
      .option("--dims", "X,Y,Z", "override the grid resolution over the same bounds (Y up)",
              [&dims](const std::string& v) { dims = parse_dims(v); })
      .option("--grown-attributes", "simulated|constant",
              "grown edits' attributes: from the simulation (default) or the faithful constant per edit",
              &grown_attributes)
      .flag("--no-verify", "skip decoding every BC1 texel (faster; the bound is then unchecked)", &no_verify);
  if (!p.parse(argc, argv)) return 0;
  if (out_dir.empty()) fail("cumulo bake: -o DIR is required");

  bake::RecipeOptions ro;
  if (p.was_set("--seed")) ro.seed = seed;
  if (grown_attributes != "simulated" && grown_attributes != "constant")
    fail("--grown-attributes: expected simulated or constant, got %s", quote(grown_attributes).c_str());
  ro.grown_constant = grown_attributes == "constant";
  bake::Recipe recipe = bake::load_recipe(recipe_path, ro);
  bake::BakeSettings settings;
  settings.dims = dims;
  settings.voxel_size = voxel;
  settings.verify = !no_verify;
  bake::BakeResult r = bake::bake_recipe(recipe, settings);
  bake::write_bake_outputs(recipe, r, out_dir);

  const glm::uvec3 d = r.grid.dims;
  const uint64_t mod_bc1 = bake::bake_gpu_bytes("bc1", d), mod8 = bake::bake_gpu_bytes("rgba8", d);
  const uint64_t f16 = bake::bake_gpu_bytes("r16", d), fbc1 = bake::bake_gpu_bytes("bc1", d);
  const uint64_t cov = bake::bake_gpu_bytes("r8", coverage_nvdf_size(d));
  std::printf("baked %s: %u x %u x %u voxels (x, y up, z) of %.2f x %.2f x %.2f m, %zu edits, %u threads\n",
              recipe.file.c_str(), d.x, d.y, d.z, r.grid.spacing.x, r.grid.spacing.y, r.grid.spacing.z,
              recipe.edits.size(), worker_count());
  std::printf("  time: %.2f s (compose %.2f, field %.2f, modeling %.2f, bc1 field %.2f, bc1 modeling %.2f, verify %.2f)\n",
              r.timings.total, r.timings.compose, r.timings.field, r.timings.modeling, r.timings.bc1_field,
              r.timings.bc1_modeling, r.timings.verify);
  std::printf("  GPU bytes: modeling.nvdf rgba8 %.3f MB | modeling_bc1.nvdf bc1 %.3f MB | coverage.nvdf r8 %.3f MB | "
              "field.nvdf r16 %.3f MB | field_bc1.nvdf bc1 %.3f MB\n",
              mb(mod8), mb(mod_bc1), mb(cov), mb(f16), mb(fbc1));
  std::printf("  compressed path (modeling_bc1 + coverage + field_bc1): %.3f MB; at 512x64x512: %.3f MB (talk 25.166 MB, "
              "budget 25.2 MB)\n",
              mb(mod_bc1 + cov + fbc1),
              mb(bake::bake_gpu_bytes("bc1", {512, 64, 512}) * 2 + bake::bake_gpu_bytes("r8", coverage_nvdf_size({512, 64, 512}))));
  if (settings.verify) {
    const auto& f = r.field_bc1_report;
    std::printf("  field BC1: %llu texels, %llu above the 16-bit value, %llu filtered points checked, %llu above; "
                "error vs R16 mean %.3f m max %.3f m; vs float mean %.3f m max %.3f m\n",
                (unsigned long long)f.texels, (unsigned long long)f.violations, (unsigned long long)f.midpoint_checks,
                (unsigned long long)f.midpoint_violations, f.mean_error_m, f.max_error_m, f.mean_error_vs_float_m,
                f.max_error_vs_float_m);
    const auto& m = r.modeling_bc1_report;
    std::printf("  modeling BC1 RMSE: profile %.4f, detail type %.4f, density scale %.4f\n", m.rmse.x, m.rmse.y, m.rmse.z);
  }
  std::printf("  wrote %s (see bake_report.json)\n", out_dir.c_str());
  if (!slices_dir.empty()) {
    auto files = bake::write_slices(recipe, r, slices_dir);
    std::printf("  wrote %zu cross-sections to %s\n", files.size(), slices_dir.c_str());
  }
  return 0;
}

void register_bake_command(CommandRegistry& registry) {
  registry.add({"bake", "bake a cloudscape recipe into modeling and field NVDFs", run_bake_command});
}

}  // namespace cumulo::clouds
