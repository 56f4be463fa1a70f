// `cumulo run` end to end, headless on lavapipe with validation (CUMULO_VALIDATION=1 from CTest):
// exit code, stats JSON, screenshot pixel statistics, reproducibility, the graph dump, bad inputs.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using cumulo::test::run_cumulo;

namespace {

const std::string kLevel = "content/levels/sample/level.json";

fs::path temp_dir() { return cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_run_cli")); }

struct Image {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
  const uint8_t* px(int x, int y) const { return &rgba[(size_t(y) * w + x) * 4]; }
};

Image load_png(const fs::path& p) {
  Image img;
  int n = 0;
  uint8_t* data = stbi_load(p.c_str(), &img.w, &img.h, &n, 4);
  if (!data) return img;
  img.rgba.assign(data, data + size_t(img.w) * img.h * 4);
  stbi_image_free(data);
  return img;
}

// Mean RGB over rows [y0, y1).
std::array<double, 3> mean_rows(const Image& img, int y0, int y1) {
  std::array<double, 3> m{0, 0, 0};
  size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < img.w; ++x, ++n)
      for (int c = 0; c < 3; ++c) m[c] += img.px(x, y)[c];
  for (auto& v : m) v /= double(std::max<size_t>(n, 1));
  return m;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// Two pictures of one size compared: PSNR over RGB, and how many channel values differ at all.
struct Comparison {
  double psnr = 0.0, differ = 0.0;
};
Comparison compare(const Image& a, const Image& b) {
  double se = 0.0, differ = 0.0;
  for (size_t i = 0; i < a.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      const double e = double(a.rgba[i + c]) - double(b.rgba[i + c]);
      se += e * e;
      differ += e != 0.0;
    }
  return {10.0 * std::log10(255.0 * 255.0 / std::max(se / double(a.w * a.h * 3), 1e-9)), differ};
}

}  // namespace

TEST(RunCli, HelpDocumentsEveryFlag) {
  auto r = run_cumulo("run --help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* flag : {"--headless", "--frames", "--size", "--mode", "--screenshot", "--camera", "--time-of-day",
                           "--seed", "--start-at", "--stats", "--dump-graph", "--dynamic-resolution", "--budget-scale",
                           "--resolution-scale"})
    EXPECT_NE(r.output.find(flag), std::string::npos) << flag << " missing from --help:\n" << r.output;
}

TEST(RunCli, HeadlessGroundRunWritesStatsAndAPlausibleImage) {
  fs::path d = temp_dir();
  fs::path png = d / "ground.png", stats = d / "ground.json";
  auto r = run_cumulo("run " + kLevel + " --headless --frames 3 --size 320x180 --camera ground --screenshot " +
                      png.string() + " --stats " + stats.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(png.string()), std::string::npos) << "screenshot path not printed:\n" << r.output;

  auto j = nlohmann::json::parse(read_text(stats));
  EXPECT_EQ(j["frames"], 3);
  EXPECT_EQ(j["size"][0], 320);
  EXPECT_EQ(j["size"][1], 180);
  EXPECT_EQ(j["mode"], 30);
  EXPECT_EQ(j["validation_enabled"], true) << r.output;  // CTest sets CUMULO_VALIDATION=1
  EXPECT_EQ(j["validation_errors"], 0) << r.output;
  EXPECT_FALSE(j["device"]["name"].get<std::string>().empty());
  EXPECT_GT(j["peak_gpu_memory_bytes"].get<uint64_t>(), 0u);
  EXPECT_GT(j["cpu_frame_ms"]["mean"].get<double>(), 0.0);
  for (const char* pass : {"geometry", "sky", "tonemap"}) {
    ASSERT_TRUE(j["passes"].contains(pass)) << pass << "\n" << j.dump(2);
    auto& p = j["passes"][pass];
    EXPECT_GT(p["mean_ms"].get<double>(), 0.0) << pass;
    EXPECT_LE(p["min_ms"].get<double>(), p["mean_ms"].get<double>()) << pass;
    EXPECT_GE(p["max_ms"].get<double>(), p["mean_ms"].get<double>()) << pass;
  }

  Image img = load_png(png);
  ASSERT_EQ(img.w, 320);
  ASSERT_EQ(img.h, 180);
  // Top rows: sky, blue dominant and bright enough to be day.
  auto top = mean_rows(img, 0, 18);
  EXPECT_GT(top[2], top[0] + 10) << "sky is not bluish: " << top[0] << " " << top[1] << " " << top[2];
  EXPECT_GT(top[2], 90.0);
  // Bottom rows: terrain or ocean, clearly different from the sky above.
  auto bottom = mean_rows(img, 162, 180);
  double diff = std::fabs(bottom[0] - top[0]) + std::fabs(bottom[1] - top[1]) + std::fabs(bottom[2] - top[2]);
  EXPECT_GT(diff, 40.0) << "bottom rows look like the sky";
  // Not a flat image: per-row means vary.
  double lo = 1e9, hi = -1e9;
  for (int y = 0; y < img.h; y += 6) {
    auto m = mean_rows(img, y, y + 1);
    double l = m[0] + m[1] + m[2];
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
  EXPECT_GT(hi - lo, 30.0);
}

// Budget modes that hold a budget (render/dynamic_resolution.h): a budget the device cannot meet lowers the
// clouds' scale, one far above the frame leaves it at 1, and headless runs keep 1 unless asked.
TEST(RunCli, DynamicResolutionFollowsTheBudget) {
  fs::path d = temp_dir();
  auto stats_of = [&](const std::string& flags, const std::string& name) {
    fs::path stats = d / (name + ".json");
    auto r = run_cumulo("run " + kLevel + " --headless --frames 24 --size 160x90 --camera ground --mode 60 " + flags +
                        " --stats " + stats.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    auto j = nlohmann::json::parse(read_text(stats));
    EXPECT_EQ(j["validation_errors"], 0) << r.output;
    return j;
  };
  auto small = stats_of("--dynamic-resolution on --budget-scale 0.01", "small");
  EXPECT_EQ(small["budget"]["dynamic_resolution"], true);
  EXPECT_NEAR(small["budget"]["frame_ms"].get<double>(), 1000.0 / 60.0 * 0.01, 1e-6);
  EXPECT_FLOAT_EQ(small["resolution_scale"]["last"].get<float>(), 0.5f) << small.dump(2);
  EXPECT_GE(small["resolution_scale"]["changes"].get<int>(), 1);
  EXPECT_FLOAT_EQ(small["resolution_scale"]["max"].get<float>(), 1.0f) << "it starts at full resolution";

  auto large = stats_of("--dynamic-resolution on --budget-scale 1000", "large");
  EXPECT_FLOAT_EQ(large["resolution_scale"]["min"].get<float>(), 1.0f) << large.dump(2);
  EXPECT_EQ(large["resolution_scale"]["changes"], 0);

  auto headless = stats_of("--budget-scale 0.01", "headless");
  EXPECT_EQ(headless["budget"]["dynamic_resolution"], false) << "a headless image must not depend on the machine's speed";
  EXPECT_FLOAT_EQ(headless["resolution_scale"]["min"].get<float>(), 1.0f);
}

// A fixed --resolution-scale: the cloud march runs at half the size and the composite upsamples it; the
// picture stays the same picture (the terrain untouched, the sky close), from a quarter of the rays.
// The terrain's levels of detail at the default error (3 px) keep the picture of full detail: a coarse level's
// triangles shade from the height field's normal texture, and its coastline stays within the error.
TEST(RunCli, TheTerrainsLevelsOfDetailKeepThePictureOfFullDetail) {
  fs::path d = temp_dir();
  auto render = [&](const std::string& flags, const std::string& name) {
    fs::path png = d / (name + ".png"), stats = d / (name + ".json");
    auto r = run_cumulo("run " + kLevel + " --headless --frames 2 --size 320x180 --camera mixed --mode 60 --clouds off " +
                        flags + " --screenshot " + png.string() + " --stats " + stats.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(nlohmann::json::parse(read_text(stats))["validation_errors"], 0) << r.output;
    return load_png(png);
  };
  const auto full = render("--lod-error 0", "full"), lod = render("", "default");
  ASSERT_EQ(full.rgba.size(), lod.rgba.size());
  const auto [psnr, differ] = compare(full, lod);
  EXPECT_GT(differ, 100.0) << "the default draws full detail";
  // 34.7 dB measured; the same levels shaded by their vertices' normals (before the normal texture): 30.9 dB.
  EXPECT_GT(psnr, 33.0);
}

TEST(RunCli, ResolutionScaleUpsamplesTheCloudsIntoTheSamePicture) {
  fs::path d = temp_dir();
  auto render = [&](const std::string& flags, const std::string& name) {
    fs::path png = d / (name + ".png"), stats = d / (name + ".json"), graph = d / (name + ".txt");
    auto r = run_cumulo("run " + kLevel + " --headless --frames 8 --size 320x180 --camera ground --mode 60 " + flags +
                        " --screenshot " + png.string() + " --stats " + stats.string() + " --dump-graph " + graph.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    auto j = nlohmann::json::parse(read_text(stats));
    EXPECT_EQ(j["validation_errors"], 0) << r.output;
    return std::make_pair(load_png(png), j);
  };
  auto [full, full_stats] = render("", "full");
  auto [half, half_stats] = render("--resolution-scale 0.5", "half");
  ASSERT_EQ(full.w, 320);
  ASSERT_EQ(half.w, 320);
  ASSERT_EQ(half.h, 180);
  EXPECT_FLOAT_EQ(half_stats["resolution_scale"]["last"].get<float>(), 0.5f);
  const auto [psnr, differ] = compare(full, half);
  EXPECT_GT(differ, 1000.0) << "the scale did not reach the clouds";
  // 23.7 dB measured after 8 frames (the 1-in-16 reprojection has not converged at either scale); the clouds
  // upsampled from the wrong place (the top-left quarter stretched) score 10.7 dB.
  EXPECT_GT(psnr, 20.0) << "the upsampled clouds are another picture";
  // The terrain and the beach (the bottom rows, no cloud in front) are the same.
  auto a = mean_rows(full, 165, 180), b = mean_rows(half, 165, 180);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1.5) << "channel " << c;
  // The march's rays: one per 4x4 block of 320x180 at full scale, of 160x90 at half (the compiled graph's sizes).
  EXPECT_NE(read_text(d / "full.txt").find("clouds.sub_color image transient 80x45x1"), std::string::npos);
  EXPECT_NE(read_text(d / "half.txt").find("clouds.sub_color image transient 40x23x1"), std::string::npos)
      << read_text(d / "half.txt");
}

// The 40/60 Hz near segment marches 1 of 16 of its half-resolution pixels a frame and reprojects the rest
// (--cloud-near-reprojection 16, the default; 4 the one before): inside the Stormbird's chamber, where the near layer
// is the picture, the same picture for a sixteenth (a quarter) of the near march's rays (counted from the compiled
// graph's image sizes: a unit test times nothing).
TEST(RunCli, TheNearSegmentReprojectsIntoTheSamePicture) {
  fs::path d = temp_dir();
  auto render = [&](const std::string& n) {
    fs::path png = d / ("near" + n + ".png"), stats = d / ("near" + n + ".json"), graph = d / ("near" + n + ".txt");
    auto r = run_cumulo("run " + kLevel + " --headless --frames 16 --size 160x90 --camera lair --mode 60 --cloud-near-reprojection " +
                        n + " --screenshot " + png.string() + " --stats " + stats.string() + " --dump-graph " + graph.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    auto j = nlohmann::json::parse(read_text(stats));
    EXPECT_EQ(j["validation_errors"], 0) << r.output;
    return std::make_pair(load_png(png), j);
  };
  auto [every, every_stats] = render("1");
  auto [quarter, quarter_stats] = render("4");
  auto [sixteenth, sixteenth_stats] = render("16");
  ASSERT_EQ(every.w, 160);
  ASSERT_EQ(quarter.w, 160);
  ASSERT_EQ(sixteenth.w, 160);
  EXPECT_FALSE(every_stats["passes"].contains("clouds.reconstruct_near"));
  ASSERT_TRUE(quarter_stats["passes"].contains("clouds.reconstruct_near")) << quarter_stats["passes"].dump(2);
  ASSERT_TRUE(sixteenth_stats["passes"].contains("clouds.reconstruct_near"));
  // The near march's rays: every pixel of the 80x45 half-resolution near layer, or one per 2x2 (4x4) block of it.
  EXPECT_EQ(read_text(d / "near1.txt").find("clouds.near_sub_color"), std::string::npos);
  EXPECT_NE(read_text(d / "near4.txt").find("clouds.near_sub_color image transient 40x23x1"), std::string::npos)
      << read_text(d / "near4.txt");
  EXPECT_NE(read_text(d / "near16.txt").find("clouds.near_sub_color image transient 20x12x1"), std::string::npos)
      << read_text(d / "near16.txt");
  std::printf("  against every near pixel: 1 of 4 %.1f dB, 1 of 16 %.1f dB\n", compare(every, quarter).psnr,
              compare(every, sixteenth).psnr);
  EXPECT_GT(compare(every, quarter).psnr, 35.0);
  EXPECT_GT(compare(every, sixteenth).psnr, 35.0);
}

TEST(RunCli, SameSeedGivesIdenticalImages) {
  fs::path d = temp_dir();
  std::string args = "run " + kLevel + " --headless --frames 2 --size 160x90 --camera mixed --seed 7 --start-at 1.5 --screenshot ";
  auto a = run_cumulo(args + (d / "a.png").string());
  auto b = run_cumulo(args + (d / "b.png").string());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << b.output;
  Image ia = load_png(d / "a.png"), ib = load_png(d / "b.png");
  ASSERT_EQ(ia.rgba.size(), ib.rgba.size());
  ASSERT_FALSE(ia.rgba.empty());
  int max_diff = 0;
  for (size_t i = 0; i < ia.rgba.size(); ++i) max_diff = std::max(max_diff, std::abs(int(ia.rgba[i]) - int(ib.rgba[i])));
  EXPECT_LE(max_diff, 1) << "two runs with the same seed differ by more than 1 LSB";
}

TEST(RunCli, DumpGraphWritesTextAndGraphviz) {
  fs::path d = temp_dir();
  auto r = run_cumulo("run " + kLevel + " --headless --frames 1 --size 160x90 --dump-graph " + (d / "g.txt").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string text = read_text(d / "g.txt");
  for (const char* pass : {"geometry", "sky", "tonemap"}) EXPECT_NE(text.find(pass), std::string::npos) << text;
  r = run_cumulo("run " + kLevel + " --headless --frames 1 --size 160x90 --dump-graph " + (d / "g.dot").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string dot = read_text(d / "g.dot");
  EXPECT_NE(dot.find("digraph"), std::string::npos) << dot;
}

TEST(RunCli, TimeOfDayChangesTheLight) {
  fs::path d = temp_dir();
  std::string base = "run " + kLevel + " --headless --frames 1 --size 160x90 --camera ground --screenshot ";
  ASSERT_EQ(run_cumulo(base + (d / "noon.png").string() + " --time-of-day 12").exit_code, 0);
  ASSERT_EQ(run_cumulo(base + (d / "night.png").string() + " --time-of-day 0").exit_code, 0);
  auto noon = mean_rows(load_png(d / "noon.png"), 0, 90), night = mean_rows(load_png(d / "night.png"), 0, 90);
  EXPECT_GT(noon[0] + noon[1] + noon[2], 3.0 * (night[0] + night[1] + night[2]) + 30.0);
}

// ---- bad inputs: a clear message, exit code 1, never a crash (a crash would be >= 128)

TEST(RunCliBadInput, MissingLevel) {
  auto r = run_cumulo("run no/such/level.json --headless");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no/such/level.json"), std::string::npos) << r.output;
}

TEST(RunCliBadInput, MalformedJsonNamesLineAndColumn) {
  fs::path d = temp_dir();
  fs::path p = d / "broken.json";
  std::ofstream(p) << "{\n  \"entities\": [\n    { \"name\": \"x\", }\n  ]\n}\n";
  auto r = run_cumulo("run " + p.string() + " --headless");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(p.string() + ":3:"), std::string::npos) << r.output;
}

TEST(RunCliBadInput, MissingGltfIsNamed) {
  fs::path d = temp_dir();
  // The sample level with its models pointing at a file that does not exist.
  std::string level = read_text(kLevel);
  ASSERT_FALSE(level.empty());
  size_t n = 0;
  // Every model path ("path": "....glb") renamed.
  const std::string key = "\"path\": \"";
  for (size_t pos = 0; (pos = level.find(key, pos)) != std::string::npos;) {
    const size_t from = pos + key.size(), to = level.find('"', from);
    if (level.compare(to - 4, 4, ".glb") == 0) level.replace(from, to - from, "missing_terrain.glb"), ++n;
    pos = from;
  }
  ASSERT_GT(n, 0u) << "the sample level names no .glb";
  fs::path p = d / "missing_gltf.json";
  std::ofstream(p) << level;
  auto r = run_cumulo("run " + p.string() + " --headless");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("missing_terrain.glb"), std::string::npos) << r.output;
}

TEST(RunCliBadInput, UnknownCameraListsTheCameras) {
  auto r = run_cumulo("run " + kLevel + " --headless --camera nowhere");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(kLevel + ": no camera named \"nowhere\""), std::string::npos) << r.output;  // the level's file
  EXPECT_NE(r.output.find("ground"), std::string::npos) << r.output;
}

// A level whose only camera has no name starts from it (the default camera is the first, named or not); `--camera ""`
// is the default too; a named one it lacks is an error naming the level's file.
TEST(RunCliBadInput, AnUnnamedCameraIsTheDefault) {
  fs::path d = temp_dir();
  fs::path p = d / "unnamed_camera.json";
  std::ofstream(p) << R"({"version": 1, "entities": [
    {"components": {"Transform": {"position": [0, 10, 50], "look_at": [0, 10, 0]}, "Camera": {}}}]})";
  auto r = run_cumulo("run " + p.string() + " --headless --frames 1 --size 64x36");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_cumulo("run " + p.string() + " --headless --frames 1 --size 64x36 --camera \"\"");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_cumulo("run " + p.string() + " --headless --frames 1 --size 64x36 --camera ground");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(p.string() + ": no camera named \"ground\""), std::string::npos) << r.output;
}

TEST(RunCliBadInput, BadFlagValues) {
  auto r = run_cumulo("run " + kLevel + " --headless --size 320by180");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--size"), std::string::npos) << r.output;
  r = run_cumulo("run " + kLevel + " --headless --mode 50");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("30, 40 or 60"), std::string::npos) << r.output;
}

TEST(RunCliBadInput, BrokenShaderNamesFileAndLine) {
  // A copy of the repository's shaders with one broken line, used through CUMULO_ROOT.
  fs::path root = temp_dir() / "root";
  fs::remove_all(root);
  fs::create_directories(root);
  fs::copy("shaders", root / "shaders", fs::copy_options::recursive);
  fs::create_directory_symlink(fs::absolute("content"), root / "content");
  fs::path frag = root / "shaders/engine/geometry_lit.frag";
  std::string src = read_text(frag);
  size_t main_pos = src.find("void main() {");
  ASSERT_NE(main_pos, std::string::npos);
  src.insert(main_pos + 13, "\n  this is not glsl;");
  std::ofstream(frag) << src;
  // The engine compiles its shaders from <repo root>/shaders at run time; point the root at the copy.
  auto r = run_cumulo("run " + fs::absolute(kLevel).string() + " --headless --size 160x90", "CUMULO_ROOT=" + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("geometry_lit.frag:"), std::string::npos) << r.output;

  // A module's shader (the clouds' reconstruction, compiled while the module creates its GPU objects): the
  // same clear error, and the objects it made before are freed while the device lives (it used to abort in
  // vkDestroyImageView after the device was gone, exit 134).
  std::ofstream(frag) << read_text("shaders/engine/geometry_lit.frag");
  fs::path comp = root / "shaders/clouds/reconstruct.comp";
  src = read_text(comp);
  main_pos = src.find("void main() {");
  ASSERT_NE(main_pos, std::string::npos);
  src.insert(main_pos + 13, "\n  this is not glsl;");
  std::ofstream(comp) << src;
  r = run_cumulo("run " + fs::absolute(kLevel).string() + " --headless --size 160x90", "CUMULO_ROOT=" + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("reconstruct.comp:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("still live"), std::string::npos) << r.output;

  // A shader a pass builds on first use, missing (the envelope's shadow, made while the frame's graph is built): the
  // frame's inputs, which hold the assets' GPU images, are freed with the device's objects (it aborted, exit 134).
  std::ofstream(comp) << read_text("shaders/clouds/reconstruct.comp");
  fs::remove(root / "shaders/clouds/envelope_shadow.comp");
  r = run_cumulo("run " + fs::absolute(kLevel).string() + " --headless --size 160x90 --camera peak --frames 2",
                 "CUMULO_ROOT=" + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("envelope_shadow.comp: shader file not found"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("still live"), std::string::npos) << r.output;
}
