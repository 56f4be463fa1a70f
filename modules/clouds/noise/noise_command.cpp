#include "modules/clouds/noise/noise_command.h"

// Format choice for the 2023 voxel noise: RGBA8 by default, the talk's 4-bit R4G4B4A4 with --format 4.
// Measured 2026-11-22 (seed 1, 128^3, `cumulo noise -o DIR --format both`; error against the float texels):
//
//                        level 0 / all mips   PSNR    max err   up-rez density error (test profile, 2M texels)
//   R4G4B4A4 (talk)      4,194,304 / 4,793,490 B   34.3 dB  0.0333    mean 0.0044  rmse 0.019  max 0.77  >0.05 on 1.6 %
//   RGBA8                8,388,608 / 9,586,980 B   58.9 dB  0.0020    mean 0.00026 rmse 0.0018 max 0.19  >0.05 on 0.03 %
//   (mean up-rez density 0.348; the large maxima sit where the erosion just reaches zero and the
//   talk's density^0.3 sharpening magnifies any step, which is where 4-bit steps show as terracing.)
//
// Fetch cost on lavapipe (tests/modules/clouds/noise/cumulo_noise_fetch_bench): R4G4B4A4_UNORM_PACK16 is
// not sampleable there (optional format; llvmpipe 15 / Mesa 22.3.6), B4G4R4A4_UNORM_PACK16 (mandatory)
// with an r<->b view swizzle is. Instructions per trilinear fetch under callgrind (steps 64 vs 16,
// 4096 invocations): 4-bit 106, RGBA8 70 (4-bit decode is 1.5x the work on a CPU device). Wall-clock
// timestamps on the shared 2-core machine (load ~15) were inconclusive: 128^3 at LOD 0, 4-bit 128-136 ms
// vs RGBA8 130-177 ms; at LOD 2 4-bit 20-44 ms vs RGBA8 9-37 ms, for 1M fetches.
//
// So: 17x smaller up-rez error and cheaper fetches on lavapipe (our development and CI device) for
// 4.2 MB more GPU memory, about a sixth of one cloudscape's 25.2 MB. On a GPU the texture unit decodes
// 4-bit for free and the halved footprint is what the talk bought; `--format 4` writes that form.

#include <algorithm>
#include <cstdio>
#include <memory>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/memory_budget.h"
#include "engine/core/message.h"
#include "engine/core/progress.h"
#include "engine/core/time.h"
#include "modules/clouds/noise/noise_preview.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {

namespace {


NoiseFileInfo save(FileSet& files, const std::filesystem::path& path, const Volume& v) {
  const std::vector<uint8_t> bytes = serialize_volume(v);
  files.add(path, bytes);
  NoiseFileInfo info;
  info.path = path;
  info.encoding = encoding_name(v.encoding);
  info.width = v.size.x;
  info.height = v.size.y;
  info.depth = v.size.z;
  info.mips = v.mip_count();
  info.channels = static_cast<uint32_t>(v.channels.size());
  info.gpu_bytes_level0 = v.level_bytes(0);
  info.gpu_bytes = v.payload_bytes();
  info.file_bytes = bytes.size();
  return info;
}

// Generates one texture with a Progress line over its level-0 texels.
template <typename Gen>
NoiseTexture generate(const char* label, size_t texels, bool show, Gen&& gen) {
  std::unique_ptr<Progress> progress;
  if (show) progress = std::make_unique<Progress>(label, static_cast<double>(texels));
  NoiseTexture t = gen(progress.get());
  if (progress) progress->finish();
  return t;
}

}  // namespace

NoiseSetReport write_noise_set(const NoiseSetOptions& o) {
  Stopwatch total;
  NoiseSetReport report;
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec || !std::filesystem::is_directory(o.out_dir))
    fail("%s: cannot create the output folder (%s)", o.out_dir.string().c_str(), ec.message().c_str());

  // Peak bytes per texel of the two 128^3-class textures: float channels with mips (2 x 4 x 4 x 8/7),
  // their encoded volumes and serialized copies (about 12), rounded up.
  constexpr uint64_t kNoiseBytesPerTexel = 64;
  const uint64_t side = uint64_t(std::max(o.size, 0));
  check_memory_budget(saturating_product({side, side, side, kNoiseBytesPerTexel}),
                      strf("%s: noise textures of %d^3 texels (--size)", o.out_dir.string().c_str(), o.size));

  VoxelNoiseParams vp;
  vp.size = o.size;
  vp.seed = o.seed;
  SkyNoiseParams sp;
  sp.seed = o.seed;
  sp.base_size = o.size;
  sp.detail_size = std::max(4, o.size / 4);
  sp.curl_size = o.size;

  Stopwatch gen_clock;
  const size_t n3 = static_cast<size_t>(o.size) * o.size * o.size;
  NoiseTexture voxel = generate("noise: voxel (Curly-Alligator, Alligator)", n3, o.progress,
                                [&](Progress* p) { return generate_voxel_noise(vp, p); });
  NoiseTexture base = generate("noise: sky base (Perlin-Worley, Worley)", n3, o.progress,
                               [&](Progress* p) { return generate_sky_base(sp, p); });
  NoiseTexture detail = generate("noise: sky detail (Worley)", static_cast<size_t>(sp.detail_size) * sp.detail_size * sp.detail_size,
                                 o.progress, [&](Progress* p) { return generate_sky_detail(sp, p); });
  NoiseTexture curl2d = generate("noise: curl 2D", static_cast<size_t>(o.size) * o.size, o.progress,
                                 [&](Progress* p) { return generate_curl_2d(sp, p); });
  report.generate_seconds = gen_clock.seconds();

  // Voxel noise in the requested format(s); voxel_noise.nvdf is the one the renderer loads.
  const VolumeEncoding chosen = o.format == NoiseFormat::Bits8   ? VolumeEncoding::RGBA8
                                : o.format == NoiseFormat::Bits4 ? VolumeEncoding::R4G4B4A4
                                                                 : kVoxelNoiseEncoding;
  // One set: a failed write leaves the previous noise files as they were.
  FileSet files;
  report.files.push_back(save(files, o.out_dir / "voxel_noise.nvdf", noise_to_volume(voxel, chosen, kVoxelChannels)));
  if (o.format == NoiseFormat::Both) {
    for (VolumeEncoding e : {VolumeEncoding::R4G4B4A4, VolumeEncoding::RGBA8})
      report.files.push_back(save(files, o.out_dir / strf("voxel_noise_%s.nvdf", encoding_name(e)),
                                  noise_to_volume(voxel, e, kVoxelChannels)));
  }
  report.files.push_back(save(files, o.out_dir / "sky_noise_base.nvdf", noise_to_volume(base, VolumeEncoding::RGBA8, kSkyBaseChannels)));
  report.files.push_back(
      save(files, o.out_dir / "sky_noise_detail.nvdf", noise_to_volume(detail, VolumeEncoding::RGBA8, kSkyDetailChannels)));
  // generate_curl_2d stores c / max|c| * 0.5 + 0.5; the decode range maps it back to curl units.
  const float cr = curl2d.signed_range;
  report.files.push_back(save(files, o.out_dir / "curl_noise.nvdf", noise_to_volume(curl2d, VolumeEncoding::RGBA8, curl_channels(cr))));

  if (o.previews) {
    files.add(o.out_dir / "voxel_noise_preview.png", encode_noise_preview(voxel));
    files.add(o.out_dir / "sky_noise_base_preview.png", encode_noise_preview(base));
    files.add(o.out_dir / "sky_noise_detail_preview.png", encode_noise_preview(detail));
    files.add(o.out_dir / "curl_noise_preview.png", encode_noise_preview(curl2d));
  }
  files.commit();

  if (o.measure) {
    for (VolumeEncoding e : {VolumeEncoding::R4G4B4A4, VolumeEncoding::RGBA8})
      report.voxel_quality.push_back({encoding_name(e), quantization_error(voxel, e), uprez_error(voxel, e)});
  }
  report.total_seconds = total.seconds();
  return report;
}

std::string format_noise_report(const NoiseSetReport& r) {
  std::string s;
  for (const NoiseFileInfo& f : r.files) {
    s += strf("  %-28s %4ux%-4ux%-4u %u ch %-9s %u mips  GPU %9llu B (level 0 %9llu B)  file %9llu B\n",
              f.path.filename().string().c_str(), f.width, f.height, f.depth, f.channels, f.encoding.c_str(), f.mips,
              static_cast<unsigned long long>(f.gpu_bytes), static_cast<unsigned long long>(f.gpu_bytes_level0),
              static_cast<unsigned long long>(f.file_bytes));
  }
  for (const NoiseQuality& q : r.voxel_quality) {
    s += strf("  voxel noise as %-9s PSNR dB (R G B A):", q.encoding.c_str());
    for (const ChannelError& c : q.channels) s += strf(" %.1f", c.psnr_db);
    s += "  max err:";
    for (const ChannelError& c : q.channels) s += strf(" %.4f", c.max_abs);
    s += strf("\n      up-rez density error vs float: mean %.5f  rmse %.5f  max %.4f  >0.05 on %.3f%% of texels"
              "  (mean density %.3f)\n",
              q.uprez.mean_abs, q.uprez.rmse, q.uprez.max_abs, 100.0 * q.uprez.frac_above_0_05, q.uprez.mean_density);
  }
  s += strf("  generated in %.2fs, total %.2fs\n", r.generate_seconds, r.total_seconds);
  return s;
}

void register_noise_command(CommandRegistry& registry) {
  registry.add({"noise", "Generate the tileable cloud noise textures (.nvdf + PNG previews)", [](int argc, char** argv) {
                  NoiseSetOptions o;
                  std::string out, format;
                  bool no_previews = false, no_measure = false;
                  ArgParser p("cumulo noise",
                              "Generates the 2023 voxel-cloud noise (Curly-Alligator / Alligator, 4 channels, mips) and\n"
                              "the 2015 sky set (128^3 Perlin-Worley + Worley, 32^3 Worley, 128^2 curl) as .nvdf files.");
                  p.option("-o", "DIR", "output folder (created if missing)", &out)
                      .option("--seed", "N", "random seed (default 1); same seed, same bytes", &o.seed)
                      .option("--size", "N", "size of the 3D noises and the curl texture, a power of two (default 128)",
                              &o.size)
                      .option("--format", "4|8|both",
                              strf("voxel noise storage: 4 = R4G4B4A4 (2 B/texel), 8 = RGBA8, both = default + both "
                                   "variants (default %s)",
                                   kVoxelNoiseEncoding == VolumeEncoding::R4G4B4A4 ? "4" : "8"),
                              &format)
                      .flag("--no-previews", "skip the PNG previews", &no_previews)
                      .flag("--no-measure", "skip the 4-bit vs 8-bit quality measurement", &no_measure);
                  if (!p.parse(argc, argv)) return 0;
                  if (out.empty()) fail("cumulo noise: -o DIR is required");
                  if (!format.empty()) {
                    if (format == "4")
                      o.format = NoiseFormat::Bits4;
                    else if (format == "8")
                      o.format = NoiseFormat::Bits8;
                    else if (format == "both")
                      o.format = NoiseFormat::Both;
                    else
                      fail("cumulo noise: --format must be 4, 8 or both, got %s", quote(format, 16).c_str());
                  }
                  if (o.size < 4 || o.size > 1024 || (o.size & (o.size - 1)) != 0)
                    fail("cumulo noise: --size must be a power of two in 4..1024, got %d", o.size);
                  o.out_dir = out;
                  o.previews = !no_previews;
                  o.measure = !no_measure;
                  NoiseSetReport r = write_noise_set(o);
                  std::printf("cumulo noise: wrote %zu files to %s (seed %llu)\n%s", r.files.size(), out.c_str(),
                              static_cast<unsigned long long>(o.seed), format_noise_report(r).c_str());
                  return 0;
                }});
}

}  // namespace cumulo::clouds
