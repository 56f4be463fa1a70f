// Fetch cost of the voxel noise as R4G4B4A4_UNORM_PACK16 (the talk's 2 bytes/texel) vs R8G8B8A8_UNORM,
// on the default Vulkan device (lavapipe here; CUMULO_DEVICE picks another). Not a test: run
//   build/tests/modules/clouds/noise/cumulo_noise_fetch_bench [--size 128] [--threads 16384] [--steps 64] [--runs 7]
// It prints the median GPU time (timestamps) per format and LOD, alternating the formats within one
// run so machine noise affects both alike. Compare ratios within a run, not absolute times.
//
// On a shared, loaded machine the timings swing by 2x; instruction counts do not. With --callgrind
// only the timed dispatches are instrumented, so
//   valgrind --tool=callgrind --instr-atstart=no --smc-check=all-non-file cumulo_noise_fetch_bench
//       --callgrind --only 4 --size 32 --threads 4096 --steps 64 --runs 1 --lods 0
// counts the instructions lavapipe spends (run with --steps 16 too: the difference / (48 * threads)
// is the cost of one trilinear fetch, without the dispatch overhead).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <valgrind/callgrind.h>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/sampler.h"
#include "engine/gpu/timestamps.h"
#include "modules/clouds/noise/noise_encode.h"
#include "tests/modules/clouds/noise/noise_gpu_util.h"

using namespace cumulo;
using namespace cumulo::clouds;

int main(int argc, char** argv) {
  try {
    int size = 128;
    uint32_t threads = 16384, steps = 64, runs = 7;
    std::string only, lods = "0,2";
    bool callgrind = false;
    ArgParser p("cumulo_noise_fetch_bench", "3D fetch cost of the voxel noise: R4G4B4A4 vs RGBA8.");
    p.option("--size", "N", "noise size (power of two)", &size)
        .option("--threads", "N", "invocations per dispatch", &threads)
        .option("--steps", "N", "trilinear fetches per invocation", &steps)
        .option("--runs", "N", "timed dispatches per format and LOD (median reported)", &runs)
        .option("--only", "4|8", "measure one format only", &only)
        .option("--lods", "L,L", "mip levels to sample (0 and 2 by default)", &lods)
        .flag("--callgrind", "instrument only the timed dispatches (run under valgrind --tool=callgrind)", &callgrind);
    if (!p.parse(argc, argv)) return 0;

    VoxelNoiseParams vp;
    vp.size = size;
    NoiseTexture tex = generate_voxel_noise(vp);
    const std::vector<NoiseChannelInfo> ch = {{"r"}, {"g"}, {"b"}, {"a"}};

    gpu::Context ctx;
    std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driver_info.c_str());
    gpu::ShaderCompiler compiler({}, ctx.cache_dir() / "shaders");
    gpu::Pipeline pipeline = gpu::Pipeline::compute(
        ctx, compiler, {.shader = repo_root() / "tests/modules/clouds/noise/noise_fetch_bench.comp", .name = "noise fetch"});
    gpu::Buffer results(ctx, {.size = threads * 16ull, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "sums"});
    VkSampler sampler = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
    gpu::GpuTimer timer(ctx, 1);
    if (!timer.supported()) fail("timestamps are not supported on %s", ctx.info().name.c_str());

    const VolumeEncoding encodings[] = {VolumeEncoding::R4G4B4A4, VolumeEncoding::RGBA8};
    std::printf("sampled+linear support: R4G4B4A4_UNORM_PACK16 %s, B4G4R4A4_UNORM_PACK16 %s, R8G8B8A8_UNORM %s\n",
                test::noise_format_supported(ctx, VK_FORMAT_R4G4B4A4_UNORM_PACK16) ? "yes" : "no",
                test::noise_format_supported(ctx, VK_FORMAT_B4G4R4A4_UNORM_PACK16) ? "yes" : "no",
                test::noise_format_supported(ctx, VK_FORMAT_R8G8B8A8_UNORM) ? "yes" : "no");
    std::vector<std::unique_ptr<test::NoiseImage>> images;
    for (VolumeEncoding e : encodings)
      images.push_back(std::make_unique<test::NoiseImage>(ctx, noise_to_volume(tex, e, ch), encoding_name(e)));

    struct Params {
      uint32_t steps;
      float step_uvw, lod;
      uint32_t pad;
    };
    std::vector<float> lod_list;
    for (size_t pos = 0; pos < lods.size();) {
      size_t comma = lods.find(',', pos);
      lod_list.push_back(std::stof(lods.substr(pos, comma - pos)));
      pos = comma == std::string::npos ? lods.size() : comma + 1;
    }
    auto measured = [&](int f) { return only.empty() || only == (f == 0 ? "4" : "8"); };
    for (float lod : lod_list) {
      std::vector<double> ms[2];
      for (uint32_t run = 0; run < runs + 1; ++run) {  // run 0 warms up
        for (int f = 0; f < 2; ++f) {
          if (!measured(f)) continue;
          if (callgrind && run > 0) CALLGRIND_START_INSTRUMENTATION;
          timer.begin_frame(0);
          ctx.submit_and_wait([&](VkCommandBuffer cmd) {
            uint32_t r = timer.begin(cmd, "fetch");
            pipeline.bind(cmd);
            gpu::DescriptorWriter().sampled_image(0, images[f]->view(), sampler).storage_buffer(1, results.handle()).push(ctx, cmd, pipeline);
            pipeline.push_constants(cmd, Params{steps, 1.5f / static_cast<float>(size), lod, 0});
            pipeline.dispatch_threads(cmd, threads);
            timer.end(cmd, r);
          });
          if (callgrind && run > 0) CALLGRIND_STOP_INSTRUMENTATION;
          std::vector<gpu::TimedRange> t = timer.collect(0);
          if (run > 0 && !t.empty()) ms[f].push_back(t[0].ms);
        }
      }
      for (int f = 0; f < 2; ++f) {
        if (ms[f].empty()) continue;
        std::sort(ms[f].begin(), ms[f].end());
        double median = ms[f][ms[f].size() / 2];
        double fetches = static_cast<double>(threads) * steps;
        std::printf("lod %.0f  %-9s median %8.3f ms  (%6.1f M trilinear fetches/s, %u runs)\n", lod,
                    encoding_name(encodings[f]), median, fetches / (median * 1e-3) * 1e-6, runs);
      }
    }
    std::printf("validation errors: %u\n", ctx.validation_errors());
    return ctx.validation_errors() == 0 ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
