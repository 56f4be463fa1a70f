#pragma once
// `cumulo bench`'s measurements: the options of a run of the matrix, each configuration's samples and
// medians, and the per-view figures the targets name (bench_tables.h prints and writes them).
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "engine/core/file_io.h"
#include "engine/gpu/readback.h"
#include "engine/render/mesh_lod.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::clouds::bench {

using render::CloudAblation;

struct BenchOptions {
  std::string level = (repo_root() / "content/levels/sample/level.json").string();
  uint32_t width = 320, height = 180;
  uint32_t frames = 6;  // measured frames per run, after the warm-up
  uint32_t warmup = 3;  // lavapipe JITs on first use; the light grid is rebuilt whole on the first frame
  // The whole matrix is run this many times in turn and each run's samples pooled: a CPU device's speed
  // drifts over a minute (other work, clocks), and interleaving keeps the ratios within one run fair.
  uint32_t rounds = 3;
  std::string out;
  std::string images;  // --images: a folder for each run's converged image (the split PSNR's inputs)
  std::vector<std::string> views{"ground", "mixed", "immersed"};
  std::vector<CloudAblation> ablations{CloudAblation::Base, CloudAblation::VoxelLighting, CloudAblation::Full};
  std::vector<int> modes{30, 60};
  // The evolving view (bench_growth.h): the camera that sees the level's growing cloud ("off": not measured).
  std::string evolving = "squall";
  float lod_error_px = cumulo::render::kDefaultLodErrorPx;  // --lod-error: the terrain's level of detail (engine/render/mesh_lod.h)
};

// The full method's runs measure this many times the frames: its 8 frames take 0.3-0.6 s on a CPU device where a
// base frame alone takes 0.25-0.6 s, and the device's speed dips for a second at a time (other work on the host), so
// one dip held the median of a full run's round (ground at 30 Hz: 41, 64, 45 ms in three rounds) while the base
// runs, seconds long, averaged it away: now a full run spans about as long as a slower one, and a short dip moves no
// round's median.
constexpr uint32_t kFullMethodFrameFactor = 4;

inline uint32_t measured_frames(const BenchOptions& o, CloudAblation a) {
  return a == CloudAblation::Full ? o.frames * kFullMethodFrameFactor : o.frames;
}

// A configuration's modes (30 and 60 Hz) take turns within a round, this many chunks of its measured frames each
// (after the warm-up before the first chunk, and kChunkWarmup frames after each switch): the 60 Hz split's saving
// compares the two, and lavapipe's speed drifts by up to 1.4-2x over seconds (issue 23: the ground's split saved
// 39 % in a round whose 60 Hz run caught such a dip and 59-61 % in the others, with the two runs back to back).
constexpr uint32_t kModeChunks = 4;
constexpr uint32_t kChunkWarmup = 1;
// The measured frames of chunk `chunk` (of kModeChunks) of a run measuring `frames` in all.
inline uint32_t chunk_frames(uint32_t frames, uint32_t chunk) {
  return frames / kModeChunks + (chunk < frames % kModeChunks ? 1u : 0u);
}

// One round's medians of a run (the JSON keeps them so "in every round" can be checked, not only the
// pooled median).
struct RoundFigures {
  double cloud_ms = 0, sky_ms = 0, geometry_ms = 0, frame_ms = 0, wall_ms = 0, cpu_ms = 0;
};

struct Run {
  std::string view;
  CloudAblation ablation = CloudAblation::Full;
  int mode = 30;
  double cloud_ms = 0, geometry_ms = 0, frame_ms = 0, steps_per_pixel = 0;
  double sky_ms = 0;  // the 2.5D sky and the light shafts (is_sky_pass)
  double sky_layer_ms = 0, shafts_ms = 0;  // apart: the sum of their passes' medians
  double envelope_ms = 0;  // the Envelope method's clouds (is_envelope_pass): their own line, not in cloud_ms
  // The headless loop's wall-clock ms per frame (CPU and GPU together: on lavapipe they share the cores),
  // and its CPU part before the submit (extraction, the render graph, command recording).
  double wall_ms = 0, cpu_ms = 0;
  std::map<std::string, double> passes;  // median ms
  double psnr_vs_30hz_db = 0;  // 60 Hz runs: the final image against the 30 Hz run's (tonemapped, 8-bit)
  // Samples pooled over the rounds, and the last round's final image.
  std::vector<double> cloud, geometry, whole, steps, sky, wall, cpu;
  std::vector<RoundFigures> rounds;
  std::map<std::string, std::vector<double>> pass_samples;
  gpu::Rgba8Image image;
};

// Per view, the figures the targets name (each needs its runs in the matrix; NAN otherwise).
struct Summary {
  std::string view;
  double full_vs_base_30 = NAN, full_vs_base_60 = NAN;  // base cloud ms / full cloud ms
  double split_saving = NAN;                            // 1 - full 60 Hz / full 30 Hz cloud ms
  double split_psnr_db = NAN;                           // full 60 Hz image vs full 30 Hz
  double light_grid_share_30 = NAN, light_grid_share_60 = NAN;  // light grid ms / cloud ms (full, sun still)
  double light_grid_moving_30 = NAN, light_grid_moving_60 = NAN;  // the same with the grid updating every frame
  double fps_60 = NAN;                                  // 1000 / frame ms (GPU sum), full 60 Hz
  double fps_wall_60 = NAN;                             // 1000 / wall ms per frame, full 60 Hz
  double cpu_ms_60 = NAN;                               // the CPU part of a full 60 Hz frame
  // Per round (the targets hold "in every round"): full vs base at 30 Hz, the split's saving.
  std::vector<double> full_vs_base_30_rounds, split_saving_rounds;
};

// PSNR of two 8-bit RGBA images over RGB (dB; 99 when identical).
double psnr_rgb(const gpu::Rgba8Image& a, const gpu::Rgba8Image& b);
const Run* find_run(const std::vector<Run>& runs, const std::string& view, CloudAblation a, int mode);
double median(std::vector<double> v);
// The world-facing passes of issue 10 (the 2.5D sky, light shafts): the same in every ablation, so they
// are timed on their own and kept out of the voxel clouds' time (whose ablation ratios they would dilute).
bool is_sky_pass(const std::string& name);
bool is_sky_layer_pass(const std::string& name);  // the 2.5D sky's passes of is_sky_pass
bool is_shafts_pass(const std::string& name);     // the light shafts' passes of is_sky_pass
bool is_envelope_pass(const std::string& name);  // the Envelope method's clouds ("clouds.envelope...")
bool is_cloud_pass(const std::string& name);       // the voxel clouds' (neither of the above)
// The medians of every run's samples, and the 60 Hz runs' PSNR against their 30 Hz run.
void finish_runs(std::vector<Run>& runs, std::vector<Run>& moving);
std::vector<Summary> summarize(const std::vector<Run>& runs, const std::vector<Run>& moving,
                               const std::vector<std::string>& views);

}  // namespace cumulo::clouds::bench
