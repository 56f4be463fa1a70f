#pragma once
// Shared by the cloud renderer tests: a tiny baked cloudscape and noise (made once per process in a
// per-process temp folder), and a Vulkan fixture that renders one frame of the cloud passes over a
// given scene colour and depth and reads back the scene colour, the cloud colour and the cloud depth.
//
// The test cloudscape: a 512 x 256 x 512 m box at 8 m voxels (64 x 32 x 64), centred on the origin
// with its base at y = 0, holding one eroded sphere of radius 100 m at (0, 128, 0), billowy. The
// camera looks at it from 400 m along +Z. The noise is the voxel noise at 32^3 (fast to generate).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include "engine/core/png.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/readback.h"
#include "engine/render/graph/executor.h"
#include "engine/scene/camera.h"
#include "modules/clouds/bake/bake.h"
#include "modules/clouds/noise/noise_encode.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/engine/gpu/gpu_test_util.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds::render::test {

namespace fs = std::filesystem;

inline constexpr glm::vec3 kCloudCentre{0.0f, 128.0f, 0.0f};
inline constexpr float kCloudRadius = 100.0f;

inline const char* kTestRecipe = R"({
  "name": "render_test", "seed": 3, "voxel_size": 8,
  "bounds": {"min": [-256, 0, -256], "max": [256, 256, 256]},
  "profile": {"depth": 64, "exponent": 1.0},
  "edits": [
    {"type": "sphere", "radius": 100, "position": [0, 128, 0], "detail_type": 0.8, "density_scale": 1.0,
     "erode": {"amplitude": 12, "frequency": 0.02, "octaves": 2}}
  ]
})";

// The folder of test data, made on first use in this process.
struct TestData {
  fs::path root, cloudscape, empty, noise;
};
inline const TestData& test_data() {
  static TestData d = [] {
    TestData t;
    t.root = cumulo::test::fresh_temp_dir("cumulo_cloud_render");
    t.cloudscape = t.root / "cloudscape";
    bake::Recipe recipe = bake::parse_recipe_text(kTestRecipe, "render_test.json", t.root);
    bake::BakeSettings settings;
    settings.show_progress = false;
    bake::BakeResult result = bake::bake_recipe(recipe, settings);
    bake::write_bake_outputs(recipe, result, t.cloudscape);
    // An empty cloudscape: the same box with its sphere cut away by a larger box subtracted after it.
    std::string reordered = kTestRecipe;
    reordered.replace(reordered.rfind("]"), 1,
                      ", {\"type\": \"box\", \"op\": \"subtract\", \"size\": [800, 800, 800], \"position\": [0, 128, 0]}]");
    bake::Recipe er = bake::parse_recipe_text(reordered, "render_test_empty.json", t.root);
    bake::BakeResult eres = bake::bake_recipe(er, settings);
    t.empty = t.root / "empty";
    bake::write_bake_outputs(er, eres, t.empty);
    VoxelNoiseParams np;
    np.size = 32;
    NoiseTexture tex = generate_voxel_noise(np);
    t.noise = t.root / "voxel_noise.nvdf";
    save_volume(t.noise, noise_to_volume(tex, VolumeEncoding::RGBA8,
                                         {{"curly_low"}, {"curly_high"}, {"alligator_low"}, {"alligator_high"}}));
    return t;
  }();
  return d;
}

// A test asset in the 512 x 256 x 512 m test box (8 m voxels, seed 3, billowy), its profile ramping over
// `profile_depth` m, from the recipe's `edits_json` array, baked into test_data().root / `name` (callers keep it in a
// static: once per process).
inline fs::path baked_test_asset(const std::string& name, int profile_depth, const std::string& edits_json) {
  const fs::path out = test_data().root / name;
  const std::string text = "{\"name\": \"" + name + "_test\", \"seed\": 3, \"voxel_size\": 8,"
                           " \"bounds\": {\"min\": [-256, 0, -256], \"max\": [256, 256, 256]},"
                           " \"profile\": {\"depth\": " + std::to_string(profile_depth) + ", \"exponent\": 1.0},"
                           " \"defaults\": {\"detail_type\": 0.8}, \"edits\": " + edits_json + "}";
  bake::Recipe recipe = bake::parse_recipe_text(text, name + "_test.json", test_data().root);
  bake::BakeSettings settings;
  settings.show_progress = false;
  bake::write_bake_outputs(recipe, bake::bake_recipe(recipe, settings), out);
  return out;
}

// A hollow cloud (issue 21's chamber): a sphere of r = 120 m at kCloudCentre with a sphere of r = 50 m cut out of
// its middle, clear air walled by 70 m of cloud.
inline const fs::path& chamber_cloudscape() {
  static const fs::path dir = baked_test_asset("chamber", 32, R"([
      {"type": "sphere", "radius": 120, "position": [0, 128, 0]},
      {"type": "sphere", "op": "subtract", "radius": 50, "position": [0, 128, 0]}])");
  return dir;
}

// A flat cloud (issue 21's lateral leak): a sheet 400 x 60 x 400 m centred at kCloudCentre.
inline const fs::path& sheet_cloudscape() {
  static const fs::path dir = baked_test_asset("sheet", 24, R"([{"type": "box", "size": [400, 60, 400], "position": [0, 128, 0]}])");
  return dir;
}

// Weather coverage (issue 20): two spheres in the test box, both r = 60 m at y = 128, left (x = -120) with
// coverage threshold 0 (present at any coverage), right (x = +120) with 0.6 (whole at coverage >= 0.6, gone at
// <= 0.4).
inline constexpr glm::vec3 kCoverageLeft{-120.0f, 128.0f, 0.0f}, kCoverageRight{120.0f, 128.0f, 0.0f};
inline constexpr float kCoverageRadius = 60.0f;
inline const fs::path& coverage_cloudscape() {
  static const fs::path dir = baked_test_asset("coverage", 48, R"([
      {"type": "sphere", "radius": 60, "position": [-120, 128, 0]},
      {"type": "sphere", "radius": 60, "position": [120, 128, 0], "coverage": 0.6}])");
  return dir;
}

// Per-pixel results of one frame (row-major, top row first).
struct Frame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec4> hdr;    // scene colour after the clouds
  std::vector<glm::vec4> color;  // cloud radiance + transmittance
  std::vector<glm::vec4> depth;  // opacity-0.5 distance, steps, segment end
  glm::vec4 at(uint32_t x, uint32_t y) const { return hdr[size_t(y) * width + x]; }
  float opacity(uint32_t x, uint32_t y) const { return 1.0f - color[size_t(y) * width + x].a; }
  double mean_steps() const {
    double s = 0;
    for (const glm::vec4& d : depth) s += d.y;
    return s / double(depth.size());
  }
};

// Reinhard-mapped luminance-free comparison metric: PSNR of x / (1 + x) per channel, over the image.
inline double psnr(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  double se = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = a[i][c] / (1.0 + a[i][c]), y = b[i][c] / (1.0 + b[i][c]);
      se += (x - y) * (x - y);
    }
  const double mse = se / double(a.size() * 3);
  return mse <= 0 ? 99.0 : 10.0 * std::log10(1.0 / mse);
}

// Writes an HDR image (Reinhard, sRGB-ish gamma) when CUMULO_CLOUD_TEST_IMAGES names a folder.
inline void maybe_write_png(const std::string& name, uint32_t w, uint32_t h, const std::vector<glm::vec4>& px) {
  const char* dir = std::getenv("CUMULO_CLOUD_TEST_IMAGES");
  if (!dir || !*dir) return;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = std::max(px[i][c], 0.0f);
      rgb[i * 3 + c] = uint8_t(std::lround(std::pow(v / (1.0f + v), 1.0f / 2.2f) * 255.0f));
    }
  fs::create_directories(dir);
  cumulo::write_png(fs::path(dir) / (name + ".png"), rgb.data(), w, h, 3);
}

class CloudRenderFixture : public gpu::test::GpuTest {
 protected:
  static constexpr uint32_t kWidth = 160, kHeight = 90;

  void SetUp() override {
    GpuTest::SetUp();
    if (HasFatalFailure()) return;
    library_ = std::make_unique<gpu::PipelineLibrary>(ctx());
    assets_ = std::make_unique<CloudAssetCache>(ctx());
    grid_desc_.light_grid_size = {32, 16, 32};
    res_ = create_cloud_resources(ctx(), *library_, assets_->noise(test_data().noise), grid_desc_);
    executor_ = std::make_unique<cumulo::render::Executor>(ctx());
    set_size(kWidth, kHeight);
  }
  void TearDown() override {
    if (ctx_) ctx_->wait_idle();
    executor_.reset();
    res_.reset();
    assets_.reset();
    library_.reset();
    pattern_.reset();
    depth_.reset();
    readback_hdr_.reset();
    readback_color_.reset();
    readback_depth_.reset();
    GpuTest::TearDown();
  }

  // (Re)creates the scene images and readback buffers for a size; the scene colour is `background`
  // (or a per-pixel pattern when `pattern` is set) and the depth is the far plane everywhere.
  void set_size(uint32_t w, uint32_t h) {
    width_ = w, height_ = h;
    pattern_ = gpu::Image(ctx(), gpu::ImageDesc::tex2d(w, h, VK_FORMAT_R16G16B16A16_SFLOAT,
                                                       VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 1,
                                                       "test.scene_color"));
    depth_ = gpu::Image(ctx(), gpu::ImageDesc::tex2d(w, h, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                     "test.scene_depth"));
    const VkDeviceSize n = VkDeviceSize(w) * h;
    readback_hdr_ = gpu::Buffer(ctx(), {n * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "test.hdr"});
    readback_color_ = gpu::Buffer(ctx(), {n * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "test.color"});
    readback_depth_ = gpu::Buffer(ctx(), {n * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "test.depth"});
    set_background([](uint32_t, uint32_t) { return glm::vec4(0.2f, 0.3f, 0.5f, 1.0f); });
    set_depth(std::vector<float>(n, 0.0f));
  }
  template <class F>
  void set_background(F f) {
    background_.assign(size_t(width_) * height_, glm::vec4(0.0f));
    std::vector<uint16_t> halfs(background_.size() * 4);
    for (uint32_t y = 0; y < height_; ++y)
      for (uint32_t x = 0; x < width_; ++x) {
        const glm::vec4 v = f(x, y);
        for (int c = 0; c < 4; ++c) {
          halfs[(size_t(y) * width_ + x) * 4 + c] = glm::packHalf1x16(v[c]);
          background_[size_t(y) * width_ + x][c] = glm::unpackHalf1x16(halfs[(size_t(y) * width_ + x) * 4 + c]);
        }
      }
    pattern_.upload({{halfs.data(), halfs.size() * 2}});
  }
  void set_depth(const std::vector<float>& d) { depth_.upload({{d.data(), d.size() * 4}}); }

  scene::CameraView camera(glm::vec3 pos = {0.0f, 128.0f, 400.0f}, glm::vec3 target = kCloudCentre,
                           float fov_deg = 50.0f) const {
    scene::Camera cam;
    cam.fov_y_deg = fov_deg;
    return scene::make_camera_view(scene::Transform::look_at(pos, target), cam, float(width_) / float(height_));
  }
  // Frame `k` of a camera flying sideways past the cloud: 8 m and 1 degree of yaw per frame.
  scene::CameraView flying_camera(int k) const {
    const glm::vec3 pos(-40.0f + 8.0f * k, 128.0f, 400.0f);
    const float yaw = glm::radians(1.0f * k);
    return camera(pos, pos + glm::vec3(-std::sin(yaw) * 400.0f + 40.0f - 8.0f * k, 0.0f, -std::cos(yaw) * 400.0f));
  }
  // A wall across the pixels selected by `where`, at `distance` m along each pixel's ray.
  template <class F>
  std::vector<float> wall_depth(const scene::CameraView& cam, float distance, F where) const {
    std::vector<float> d(size_t(width_) * height_, 0.0f);
    for (uint32_t y = 0; y < height_; ++y)
      for (uint32_t x = 0; x < width_; ++x) {
        if (!where(x, y)) continue;
        const glm::vec2 ndc((x + 0.5f) / width_ * 2.0f - 1.0f, (y + 0.5f) / height_ * 2.0f - 1.0f);
        d[size_t(y) * width_ + x] = cam.project(cam.position + cam.ray_direction(ndc) * distance).z;
      }
    return d;
  }

  CloudFrameInputs inputs(const std::shared_ptr<const CloudAsset>& asset, const scene::CameraView& cam) const {
    CloudFrameInputs in;
    in.camera = cam;
    in.sun_direction = glm::normalize(glm::vec3(0.3f, 0.8f, -0.4f));
    in.sun_color = glm::vec3(6.0f, 5.6f, 5.0f);
    in.ambient_color = glm::vec3(0.35f, 0.45f, 0.6f);
    CloudInstance inst;
    inst.asset = asset;
    in.instances.push_back(inst);
    in.settings.temporal = false;
    in.settings.animated_jitter_distance_m = 0.0f;  // static jitter: frames are reproducible
    return in;
  }
  std::shared_ptr<const CloudAsset> asset(const CloudFormats& f = {}, const fs::path& dir = {}) {
    return assets_->cloudscape(dir.empty() ? test_data().cloudscape : dir, f);
  }

  // `frames` frames of a still camera from a fresh history (a camera cut, frame indices 100, 101, ...) with
  // reprojection `block`; the last frame, and the first in `first` when given.
  Frame render_settling(CloudFrameInputs in, uint32_t block, int frames, Frame* first = nullptr) {
    in.settings.reprojection_block = block;
    in.camera_cut = true;
    Frame f;
    for (int k = 0; k < frames; ++k) {
      in.frame_index = 100 + k;
      f = render(in);
      in.camera_cut = false;
      if (k == 0 && first) *first = f;
    }
    return f;
  }

  // One frame: scene colour <- pattern, clouds, readbacks. Waits for the GPU.
  Frame render(const CloudFrameInputs& in) {
    using namespace cumulo::render;
    RenderGraph g({width_, height_});
    const TextureHandle pattern =
        g.import_texture("test.scene_color", TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, width_, height_),
                         pattern_.handle(), pattern_.view(), ResourceState::shader_read_only());
    const TextureHandle depth = g.import_texture("test.scene_depth", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, width_, height_),
                                                 depth_.handle(), depth_.view(), ResourceState::shader_read_only());
    TextureHandle hdr = g.create_texture("hdr", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT));
    const uint32_t w = width_, h = height_;
    auto copy_region = [w, h]() {
      VkImageCopy r{};
      r.srcSubresource = r.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      r.extent = {w, h, 1};
      return r;
    };
    g.add_pass("test.scene", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(pattern, Usage::TransferSrc);
          hdr = b.write(hdr, Usage::TransferDst);
        },
        [pattern, hdr, copy_region](PassContext& c) {
          VkImageCopy r = copy_region();
          vkCmdCopyImage(c.cmd(), c.image(pattern), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.image(hdr),
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &r);
        });
    CloudPassOutputs outs;
    hdr = add_cloud_passes(*res_, g, in, hdr, depth, &outs);
    BufferHandle rb_hdr = g.import_buffer("test.rb_hdr", readback_hdr_.handle(), readback_hdr_.size(),
                                          ResourceState::host_read(), ResourceState::host_read());
    BufferHandle rb_color = g.import_buffer("test.rb_color", readback_color_.handle(), readback_color_.size(),
                                            ResourceState::host_read(), ResourceState::host_read());
    BufferHandle rb_depth = g.import_buffer("test.rb_depth", readback_depth_.handle(), readback_depth_.size(),
                                            ResourceState::host_read(), ResourceState::host_read());
    const bool clouds = outs.color.valid();
    g.add_pass("test.readback", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(hdr, Usage::TransferSrc);
          rb_hdr = b.write(rb_hdr, Usage::TransferDst);
          if (clouds) {
            b.read(outs.color, Usage::TransferSrc);
            b.read(outs.depth, Usage::TransferSrc);
            rb_color = b.write(rb_color, Usage::TransferDst);
            rb_depth = b.write(rb_depth, Usage::TransferDst);
          }
        },
        [hdr, outs, rb_hdr, rb_color, rb_depth, clouds, w, h](PassContext& c) {
          VkBufferImageCopy r{};
          r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          r.imageExtent = {w, h, 1};
          vkCmdCopyImageToBuffer(c.cmd(), c.image(hdr), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb_hdr), 1, &r);
          if (clouds) {
            vkCmdCopyImageToBuffer(c.cmd(), c.image(outs.color), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb_color), 1, &r);
            vkCmdCopyImageToBuffer(c.cmd(), c.image(outs.depth), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb_depth), 1, &r);
          }
        });
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { executor_->execute(g, cmd); });
    Frame f;
    f.width = w, f.height = h;
    const size_t n = size_t(w) * h;
    std::vector<uint16_t> halfs(n * 4);
    auto unpack = [&](gpu::Buffer& b, std::vector<glm::vec4>& out) {
      b.download(halfs.data(), halfs.size() * 2);
      out.resize(n);
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) out[i][c] = gpu::half_to_float(halfs[i * 4 + c]);
    };
    unpack(readback_hdr_, f.hdr);
    if (clouds) {
      unpack(readback_color_, f.color);
      f.depth.resize(n);
      readback_depth_.download(f.depth.data(), n * 16);
    } else {
      f.color.assign(n, glm::vec4(0, 0, 0, 1));
      f.depth.assign(n, glm::vec4(1e6f, 0, 0, 0));
    }
    return f;
  }

  double pass_ms(const std::string& name) const { return executor_->pass_ms(name); }

  uint32_t width_ = 0, height_ = 0;
  std::vector<glm::vec4> background_;  // exactly as stored (half precision)
  CloudResourcesDesc grid_desc_;
  std::unique_ptr<gpu::PipelineLibrary> library_;
  std::unique_ptr<CloudAssetCache> assets_;
  CloudResourcesPtr res_;
  std::unique_ptr<cumulo::render::Executor> executor_;
  gpu::Image pattern_, depth_;
  gpu::Buffer readback_hdr_, readback_color_, readback_depth_;
};

}  // namespace cumulo::clouds::render::test
