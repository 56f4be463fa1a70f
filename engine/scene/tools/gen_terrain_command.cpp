// `cumulo gen-terrain`: writes the sample archipelago .glb (see terrain_gen.h).
#include <cmath>
#include <cstdio>

#include "engine/core/args.h"
#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/time.h"
#include "engine/scene/tools/terrain_gen.h"

namespace cumulo::scene {

namespace {

// Beach spots on the main island's shore (0.5..3 m above the sea, gentle slope), one per 30 degrees
// around it: candidates for a "ground" camera.
void print_beaches(const TerrainOptions& o) {
  Archipelago arch(o);
  Heightfield hf = sample_heightfield(arch);
  const Island& main = arch.islands().front();
  std::printf("beach spots around the main island (x, z, height, slope):\n");
  for (int a = 0; a < 360; a += 30) {
    float ang = float(a) * 3.14159265f / 180.0f;
    glm::vec2 dir(std::cos(ang), std::sin(ang));
    for (float r = 0.4f * main.radius; r < 1.8f * main.radius; r += 4.0f) {
      glm::vec2 p = main.center + dir * r;
      float h = hf.sample(p.x, p.y);
      if (h < 0.5f) break;  // left the island
      if (h > 3.0f) continue;
      float e = hf.spacing();
      float dx = hf.sample(p.x + e, p.y) - hf.sample(p.x - e, p.y), dz = hf.sample(p.x, p.y + e) - hf.sample(p.x, p.y - e);
      float slope = std::atan(std::sqrt(dx * dx + dz * dz) / (2 * e)) * 57.2958f;
      if (slope < 8.0f) {
        std::printf("  bearing %3d: (%.0f, %.0f)  h=%.2f m  slope=%.1f deg\n", a, p.x, p.y, h, slope);
        break;
      }
    }
  }
}

int run_gen_terrain(int argc, char** argv) {
  TerrainOptions o;
  std::string out;
  bool beaches = false;
  ArgParser p("cumulo gen-terrain",
              "Generate the sample level's archipelago terrain as glTF binary (deterministic: same options, same bytes).");
  p.option("-o", "FILE", "output .glb (required)", &out)
      .option("--seed", "N", "random seed (default 1)", &o.seed)
      .option("--resolution", "N", "grid vertices per side (default 257: 16 m spacing)", &o.resolution)
      .range(3, 8193)  // 8193^2 vertices is about 2 GB of glTF
      .option("--texture", "N", "base-color texture size (default 512: 8 m per texel)", &o.texture_size)
      .range(4, 16384)  // the glTF loader's image limit
      .option("--size", "METRES", "terrain side (default 4096)", &o.size_m)
      .range(0.0, 1.0e6, Open::Low)
      .flag("--beaches", "also print beach spots around the main island (for placing cameras)", &beaches);
  if (!p.parse(argc, argv)) return 0;
  if (out.empty()) throw Error("cumulo gen-terrain: -o FILE is required (see --help)");
  Stopwatch sw;
  TerrainReport r;
  std::vector<uint8_t> bytes = build_terrain_glb(o, &r);
  write_file_atomic(out, bytes);
  std::printf("wrote %s: %zu bytes, %zu vertices, %zu triangles in %zu tiles, %.2f s\n", out.c_str(), r.bytes,
              r.terrain_vertices, r.terrain_triangles, r.tiles, sw.seconds());
  std::printf("heights %.1f..%.1f m, peak at (%.0f, %.0f), land %.1f%%, %zu islands\n", r.min_height, r.max_height,
              r.peak_xz.x, r.peak_xz.y, 100.0f * r.land_fraction, r.islands.size());
  for (auto& is : r.islands)
    std::printf("  island at (%.0f, %.0f) radius %.0f m height %.0f m%s\n", is.center.x, is.center.y, is.radius,
                is.height, is.volcano ? " (volcano)" : "");
  if (beaches) print_beaches(o);
  return 0;
}

}  // namespace

void register_scene_commands(CommandRegistry& registry) {
  registry.add({"gen-terrain", "generate the sample archipelago terrain (.glb)", run_gen_terrain});
}

}  // namespace cumulo::scene
