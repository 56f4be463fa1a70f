#include "modules/clouds/bake/grow/grow_command.h"

#include <cstdio>
#include <optional>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/progress.h"
#include "modules/clouds/bake/grow/grown_cloud.h"

namespace cumulo::clouds {

int run_grow_command(int argc, char** argv) {
  std::string spec_path, out_dir;
  int steps = 0;
  ArgParser p("cumulo grow",
              "Grow a cloud with the cloud-formation simulation (buoyancy, condensation, latent heat, vorticity "
              "confinement) from a grow spec: presets humilis, mediocris, congestus, cumulonimbus, stratocumulus, "
              "fractus.");
  p.positional("SPEC", "grow spec (.json), e.g. content/levels/sample/grown/hero_congestus.json", &spec_path)
      .option("-o", "DIR", "output folder (grown.nvdf, grown.vdb with OpenVDB, grown_section.png, grow_report.json)",
              &out_dir)
      .option("--steps", "N", "override the spec's step count (a quick look; the key still names the spec)", &steps)
      .range(0.0, 100000.0);
  if (!p.parse(argc, argv)) return 0;
  if (out_dir.empty()) fail("cumulo grow: -o DIR is required");
  grow::GrowSpec spec = grow::load_grow_spec(spec_path);
  if (steps > 0) spec.steps = steps;
  const glm::ivec3 n = spec.solver.dims;
  std::printf("growing %s (%s): %d x %d x %d cells of %.1f m (%.0f m physical), %d steps of %.1f s\n", spec.file.c_str(),
              spec.preset.c_str(), n.x, n.y, n.z, spec.cell_game, spec.solver.cell, spec.steps, spec.solver.dt);
  std::fflush(stdout);
  grow::GrowReport report;
  std::optional<Progress> progress;
  progress.emplace("grow", double(spec.steps));
  grow::GrownCloud g = grow::grow_cloud(spec, &report, &*progress);
  progress->finish();
  grow::write_grow_outputs(spec, g, report, out_dir);
  std::printf("  %.1f s on %u threads; cloud %.0f x %.0f x %.0f m, base %.0f m, top %.0f m above the floor; "
              "max cloud water %.2f g/kg, updraft %.1f m/s\n",
              report.wall_seconds, report.threads, report.cloud_size.x, report.cloud_size.y, report.cloud_size.z,
              report.cloud_base_m, report.cloud_top_m, report.max_cloud_water * 1e3, report.max_updraft);
  std::printf("  water: sourced %.4g, final cloud water %.4g, advection residual %.3g (%.4f %% of the initial water)\n",
              report.water.sourced, report.water.final_cloud_water, report.water.advection_residual,
              100.0 * report.total_water_drift);
  std::printf("  wrote %s (key %s)\n", out_dir.c_str(), grow::grow_key_hex(spec).c_str());
  return 0;
}

void register_grow_command(CommandRegistry& registry) {
  registry.add({"grow", "grow a cloud with the cloud-formation simulation (grow spec -> grown volume)", run_grow_command});
}

}  // namespace cumulo::clouds
