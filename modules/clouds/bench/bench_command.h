#pragma once
// `cumulo bench`: the cloud renderer's cost table (2023 talk, "Implementation of ray-march"), measured
// on this machine's device. The sample level's cameras (ground, mixed, immersed) x the ablation steps
// (base, voxel-lighting, full) x the budget modes (30: one march; 60: near/far split): median GPU ms
// of every cloud pass and of geometry, ratios to base, steps per pixel, GPU memory per resource. A
// markdown table on stdout, JSON to --out, a progress line per run on stderr. Speed is measured here,
// never asserted by a timed test.
#include "engine/core/command.h"
#include "modules/clouds/options/clouds_run.h"

namespace cumulo::clouds {

void register_bench_command(CommandRegistry& registry, const CloudsRun& clouds);

}  // namespace cumulo::clouds
