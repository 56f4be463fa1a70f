// The Envelope method's clouds on the device (issue 24): the GPU's density against the talk's profile formula and the
// CPU mirror on a known heightfield, and the march: cone + distance step mapping draws what fixed small steps draw
// (it never steps over cloud) with far fewer steps, from outside, from above and from inside the envelope.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include <glm/gtc/packing.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/json.h"
#include "engine/gpu/readback.h"
#include "modules/clouds/envelope/envelope_bake.h"
#include "modules/clouds/envelope/envelope_query.h"
#include "modules/clouds/reference/reference_tracer.h"
#include "modules/clouds/render/envelope_layer.h"
#include "modules/clouds/scene/cloudscape_assets.h"
#include "tests/modules/clouds/render/cloud_test_util.h"

namespace cumulo::clouds::render::test {
namespace {

// A cap cloud over a Gaussian hill (peak 300 m at the origin) between 200 and 600 m above sea level, and a bank
// along the hill's west side; 128 texels over 2 km.
const char* kSpec = R"({
  "extent": {"min": [-1000, -1000], "max": [1000, 1000]}, "resolution": 128, "edge_m": 35,
  "rules": [
    {"type": "cap", "center": "peak", "radius_m": 450, "base_m": 200, "top_m": 600, "detail_type": 0.7},
    {"type": "bank", "wind_from": [-1, 0, 0], "terrain_m": [20, 250], "base_above_terrain_m": 30, "thickness_m": 160,
     "coverage": 0.9, "detail_type": 0.3}
  ]})";

float hill(float x, float z) { return 300.0f * std::exp(-(x * x + z * z) / (2.0f * 350.0f * 350.0f)); }

// The hill as the renderer's terrain (texel centres) over the maps' square.
TerrainHeightfield hill_terrain(uint32_t n) {
  TerrainHeightfield t;
  t.resolution = n;
  t.origin = glm::vec2(-1000.0f);
  t.size = glm::vec2(2000.0f);
  t.texels.resize(size_t(n) * n);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const float x = t.origin.x + (i + 0.5f) * t.size.x / n, z = t.origin.y + (j + 0.5f) * t.size.y / n;
      t.texels[size_t(j) * n + i] = glm::vec4(hill(x, z), 0.3f, 0.3f, 0.3f);
    }
  t.min_height = 0.0f, t.max_height = 300.0f;
  return t;
}

std::shared_ptr<const envelope::EnvelopeMaps> test_maps() {
  static std::shared_ptr<const envelope::EnvelopeMaps> maps = [] {
    const JsonDocument doc = parse_json_text(kSpec, "envelope_test.json");
    const envelope::OrographicClouds spec = envelope::orographic_clouds_from_json(doc.view());
    return std::make_shared<const envelope::EnvelopeMaps>(envelope::bake_envelope_maps(spec, hill));
  }();
  return maps;
}

class EnvelopeLayerTest : public CloudRenderFixture {
 protected:
  void SetUp() override {
    CloudRenderFixture::SetUp();
    if (HasFatalFailure()) return;
    layer_ = std::make_unique<EnvelopeLayer>(ctx(), *library_, prepare_sky_noise());
    readback_env_depth_ = gpu::Buffer(ctx(), {VkDeviceSize(width_) * height_ * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                              gpu::MemoryUsage::Readback, "test.env_depth"});
  }
  void TearDown() override {
    if (ctx_) ctx_->wait_idle();
    layer_.reset();
    readback_env_depth_.reset();
    CloudRenderFixture::TearDown();
  }

  CloudFrameInputs env_inputs(const scene::CameraView& cam) const {
    CloudFrameInputs in;
    in.camera = cam;
    in.sun_direction = glm::normalize(glm::vec3(0.4f, 0.7f, -0.3f));
    in.sun_color = glm::vec3(6.0f, 5.6f, 5.0f);
    in.ambient_color = glm::vec3(0.35f, 0.45f, 0.6f);
    return in;
  }

  // The envelope layer alone (one pass at full resolution): colour and depth (x opacity-0.5 distance, y density
  // samples, z the ray's end, w steps).
  Frame march(const scene::CameraView& cam, bool cone, EnvelopeMarchSettings m = {}) {
    m.cone_stepping = cone;
    m.max_steps = 4096;  // both reach the far side: the counts compare placements, not a budget
    return march_with(cam, m, env_inputs(cam));
  }
  Frame march_with(const scene::CameraView& cam, const EnvelopeMarchSettings& m, const CloudFrameInputs& in) {
    using namespace cumulo::render;
    RenderGraph g({width_, height_});
    const TextureHandle depth = g.import_texture("test.scene_depth", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, width_, height_),
                                                 depth_.handle(), depth_.view(), ResourceState::shader_read_only());
    EnvelopeDraw draw;
    draw.maps = test_maps();
    CloudFrameInputs with = in;
    if (before_march_) before_march_(g, with);
    const EnvelopeLayer::Outputs o = layer_->add_passes(g, draw, m, with, depth);
    BufferHandle rb_color = g.import_buffer("test.rb_color", readback_color_.handle(), readback_color_.size(),
                                            ResourceState::host_read(), ResourceState::host_read());
    BufferHandle rb_depth = g.import_buffer("test.rb_depth", readback_env_depth_.handle(), readback_env_depth_.size(),
                                            ResourceState::host_read(), ResourceState::host_read());
    const uint32_t w = width_, h = height_;
    g.add_pass("test.readback", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(o.color, Usage::TransferSrc);
          b.read(o.depth, Usage::TransferSrc);
          rb_color = b.write(rb_color, Usage::TransferDst);
          rb_depth = b.write(rb_depth, Usage::TransferDst);
        },
        [o, rb_color, rb_depth, w, h](PassContext& c) {
          VkBufferImageCopy r{};
          r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          r.imageExtent = {w, h, 1};
          vkCmdCopyImageToBuffer(c.cmd(), c.image(o.color), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb_color), 1, &r);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(o.depth), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(rb_depth), 1, &r);
        });
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { executor_->execute(g, cmd); });
    Frame f;
    f.width = w, f.height = h;
    const size_t n = size_t(w) * h;
    std::vector<uint16_t> halfs(n * 4);
    readback_color_.download(halfs.data(), halfs.size() * 2);
    f.color.resize(n);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) f.color[i][c] = gpu::half_to_float(halfs[i * 4 + c]);
    f.depth.resize(n);
    readback_env_depth_.download(f.depth.data(), n * 16);
    f.hdr = f.color;
    return f;
  }

  // `frames` frames of the path tracer over the envelope (its medium set in `in`), accumulated.
  ReferenceImage trace(ReferenceTracer& tracer, CloudFrameInputs& in, const EnvelopeDraw& draw, const EnvelopeMarchSettings& m,
                       int frames) {
    using namespace cumulo::render;
    for (int f = 0; f < frames; ++f) {
      RenderGraph g({width_, height_});
      const TextureHandle depth = g.import_texture("test.scene_depth", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, width_, height_),
                                                   depth_.handle(), depth_.view(), ResourceState::shader_read_only());
      TextureHandle hdr = g.create_texture("hdr", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT));
      in.envelope_medium = layer_->add_medium(g, draw, m, in);
      hdr = tracer.add_passes(g, in, CloudLightOutputs{}, hdr, depth);
      ctx().submit_and_wait([&](VkCommandBuffer cmd) { executor_->execute(g, cmd); });
    }
    return tracer.read();
  }

  static double total(const Frame& f, int channel) {
    double s = 0;
    for (const glm::vec4& d : f.depth) s += d[channel];
    return s;
  }
  static double coverage(const Frame& f) {
    double s = 0;
    for (const glm::vec4& c : f.color) s += 1.0 - c.a;
    return s / double(f.color.size());
  }

  // A square R16F texture read back (the shadow maps).
  std::vector<float> read_r16f(cumulo::render::RenderGraph& g, cumulo::render::TextureHandle tex, uint32_t n) {
    using namespace cumulo::render;
    gpu::Buffer rb(ctx(), {VkDeviceSize(n) * n * 2, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "test.rb_r16f"});
    BufferHandle h = g.import_buffer("test.rb_r16f", rb.handle(), rb.size(), ResourceState::host_read(), ResourceState::host_read());
    g.add_pass("test.readback_r16f", Queue::Graphics,
        [&](PassBuilder& b) {
          b.read(tex, Usage::TransferSrc);
          h = b.write(h, Usage::TransferDst);
        },
        [tex, h, n](PassContext& c) {
          VkBufferImageCopy r{};
          r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          r.imageExtent = {n, n, 1};
          vkCmdCopyImageToBuffer(c.cmd(), c.image(tex), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(h), 1, &r);
        });
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { executor_->execute(g, cmd); });
    std::vector<uint16_t> halfs(size_t(n) * n);
    rb.download(halfs.data(), halfs.size() * 2);
    std::vector<float> out(halfs.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = gpu::half_to_float(halfs[i]);
    return out;
  }

  // An R16F or R32F image of `n` x `n` texels, row by row.
  gpu::Image float_image(uint32_t n, VkFormat format, const std::vector<float>& values, const char* name) {
    gpu::Image img(ctx(), gpu::ImageDesc::tex2d(n, n, format, VK_IMAGE_USAGE_SAMPLED_BIT, 1, name));
    if (format == VK_FORMAT_R16_SFLOAT) {
      std::vector<uint16_t> h(values.size());
      for (size_t i = 0; i < h.size(); ++i) h[i] = glm::packHalf1x16(values[i]);
      img.upload({{h.data(), h.size() * 2}});
    } else {
      img.upload({{values.data(), values.size() * 4}});
    }
    return img;
  }

  std::unique_ptr<EnvelopeLayer> layer_;
  gpu::Buffer readback_env_depth_;
  // Called on each march's graph and inputs before the layer's passes (a test's shadow maps).
  std::function<void(cumulo::render::RenderGraph&, CloudFrameInputs&)> before_march_;
};

TEST_F(EnvelopeLayerTest, TheGpuProfileIsTheTalksFormulaOnAKnownHeightfield) {
  const auto maps = test_maps();
  std::vector<glm::vec3> points;
  // A column through the cap's middle (full coverage, far inside the side), and points scattered over the map.
  for (int k = 0; k <= 40; ++k) points.emplace_back(30.0f, 180.0f + 11.0f * k, -20.0f);
  for (int k = 0; k < 400; ++k) {
    const float a = 0.7f * k, r = 2.3f * k;
    points.emplace_back(r * std::cos(a), 20.0f + 1.6f * k, r * std::sin(a));
  }
  EnvelopeDraw draw;
  draw.maps = maps;
  const std::vector<glm::vec4> gpu = layer_->probe(draw, {}, env_inputs(camera()), points);
  ASSERT_EQ(gpu.size(), points.size());
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const envelope::EnvelopeSample cpu = envelope::sample_envelope(*maps, points[i]);
    EXPECT_NEAR(gpu[i].y, cpu.profile, 2e-3f) << "profile at " << points[i].x << ", " << points[i].y << ", " << points[i].z;
    if (cpu.profile > 0.0f) ++inside;
  }
  EXPECT_GT(inside, 60);
  // In the cap's middle: the talk's product of the three gradients, over its peak.
  const envelope::EnvelopeSample mid = envelope::sample_envelope(*maps, points[0]);
  const float bottom = mid.shape.x, top = mid.shape.y;
  EXPECT_NEAR(bottom, 200.0f, 1.0f);
  EXPECT_NEAR(top, 600.0f, 1.0f);
  for (int k = 0; k <= 40; ++k) {
    const float y = points[size_t(k)].y;
    const float hf = std::clamp((y - bottom) / (top - bottom), 0.0f, 1.0f);
    const float talk = std::pow(1.0f - hf, 1.5f) * std::pow(hf, 2.0f) * 1.0f;  // edge gradient 1: 35 m inside
    EXPECT_NEAR(gpu[size_t(k)].y, talk / 0.0916133f, 2e-3f) << "y " << y;
    EXPECT_NEAR(gpu[size_t(k)].z, hf, 1e-3f) << "y " << y;
  }
  // Its peak at a height fraction of 4/7 is 1 (the normalisation).
  const std::vector<glm::vec4> peak =
      layer_->probe(draw, {}, env_inputs(camera()), {glm::vec3(30.0f, bottom + (top - bottom) * 4.0f / 7.0f, -20.0f)});
  EXPECT_NEAR(peak[0].y, 1.0f, 2e-3f);
}

// The march's picture with cone + distance step mapping against fixed small steps everywhere in the envelope's box
// (the talk's "before"), at a camera outside, above and inside the envelope.
TEST_F(EnvelopeLayerTest, ConeSteppingNeverStepsOverCloudAndTakesFewerSteps) {
  struct View {
    const char* name;
    glm::vec3 pos, target;
    double min_ratio;  // inside the envelope every step is a small one either way: never more
  };
  // Measured (lavapipe, 160x90): fixed / cone steps 4.85, 4.78, 1.13 at 50.4, 49.5, 99 dB (the 300 m noise tile).
  const View views[] = {{"side", {0.0f, 150.0f, 1400.0f}, {0.0f, 350.0f, 0.0f}, 3.0},
                        {"above", {700.0f, 1200.0f, 900.0f}, {0.0f, 300.0f, 0.0f}, 3.0},
                        {"inside", {-60.0f, 380.0f, 120.0f}, {-400.0f, 330.0f, -200.0f}, 0.999}};
  for (const View& v : views) {
    const scene::CameraView cam = camera(v.pos, v.target, 60.0f);
    const Frame cone = march(cam, true), fixed = march(cam, false);
    maybe_write_png(std::string("envelope_") + v.name + "_cone", width_, height_, cone.color);
    maybe_write_png(std::string("envelope_") + v.name + "_fixed", width_, height_, fixed.color);
    const double db = psnr(cone.color, fixed.color);
    const double ratio = total(fixed, 3) / std::max(total(cone, 3), 1.0);
    std::printf("envelope %s: cloud cover %.3f (fixed %.3f), PSNR %.1f dB, steps fixed / cone %.2f (%.0f / %.0f), "
                "density samples %.0f / %.0f\n",
                v.name, coverage(cone), coverage(fixed), db, ratio, total(fixed, 3), total(cone, 3), total(fixed, 1),
                total(cone, 1));
    EXPECT_GT(coverage(fixed), 0.02) << v.name << ": the view shows the envelope";
    EXPECT_GT(db, 40.0) << v.name;
    EXPECT_NEAR(coverage(cone), coverage(fixed), 0.01) << v.name;
    EXPECT_GT(ratio, v.min_ratio) << v.name;
  }
}

// The CPU's density query (envelope_query.h) is the GPU's density: at points up through the cap and out over the bank,
// with the wind's scroll, a weather's coverage and density and a wider edge.
TEST_F(EnvelopeLayerTest, TheCpuDensityQueryIsTheGpusDensity) {
  const auto maps = test_maps();
  EnvelopeDraw draw;
  draw.maps = maps;
  draw.density = 1.3f, draw.coverage = 0.8f, draw.edge_m = 50.0f;
  draw.wind_direction = glm::vec3(1.0f, 0.0f, 0.4f), draw.wind_speed = 7.0f;
  CloudFrameInputs in = env_inputs(camera());
  in.time = 123.25;
  std::vector<glm::vec3> points;
  for (int k = 0; k < 3000; ++k) {
    const float a = 0.37f * k, r = 0.15f * k;  // a spiral up through the cap and out over the bank
    points.emplace_back(r * std::cos(a), 150.0f + 0.15f * k, r * std::sin(a));
  }
  const std::vector<glm::vec4> gpu = layer_->probe(draw, {}, in, points);
  const envelope::EnvelopeDensityQuery q = envelope::EnvelopeDensityQuery::load(maps, prepare_sky_noise());
  envelope::EnvelopeLook look;
  look.density = draw.density, look.coverage = draw.coverage, look.edge_m = draw.edge_m;
  look.wind_direction = draw.wind_direction, look.wind_speed = draw.wind_speed;
  double err = 0.0, worst = 0.0;
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const float cpu = q.density(look, points[i], in.time);
    const double e = std::abs(double(cpu) - gpu[i].x);
    err += e, worst = std::max(worst, e);
    if (gpu[i].x > 0.05f) ++inside;
  }
  err /= double(points.size());
  std::printf("envelope density query: %zu points, %d in cloud, |CPU - GPU| mean %.5f, worst %.4f (density up to %.1f)\n",
              points.size(), inside, err, worst, look.density * look.density_scale);
  EXPECT_GT(inside, 200);
  EXPECT_LT(err, 2e-3);
  EXPECT_LT(worst, 0.06);
  EXPECT_EQ(q.density(look, glm::vec3(5000.0f, 300.0f, 0.0f), in.time), 0.0f);  // off the maps
}

// The envelope's shadow on the terrain: each texel of its map is the light's transmittance along its ray from the first
// terrain it meets coming down to the envelope's top, against the same integral on the CPU (fine steps through the
// GPU's own density, probed); folded into a voxel clouds' map it multiplies it.
TEST_F(EnvelopeLayerTest, TheShadowOnTheTerrainIsTheLightsTransmittanceThroughTheEnvelope) {
  using namespace cumulo::render;
  constexpr uint32_t kTexels = 48;
  layer_->set_terrain(hill_terrain(256));
  EnvelopeDraw draw;
  draw.maps = test_maps();
  EnvelopeMarchSettings m;
  m.detail_erosion = 0.0f;  // the probe's density is then the light samples' (no high-frequency erosion)
  m.shadow_texels = kTexels;
  m.combined_shadow_texels = kTexels;
  const CloudFrameInputs in = env_inputs(camera());
  const glm::vec3 l = glm::normalize(in.sun_direction);
  RenderGraph g({width_, height_});
  const LightShadowMap map = layer_->add_shadow_passes(g, draw, m, in, LightShadowMap{});
  ASSERT_TRUE(map.texture.valid());
  const std::vector<float> gpu = read_r16f(g, map.texture, kTexels);

  // The CPU's integral at every third texel: 2 m steps from the top down to the hill.
  std::vector<glm::vec3> points;
  std::vector<std::pair<size_t, size_t>> spans;  // per texel checked: its points [first, last)
  std::vector<size_t> texels;
  const float top = test_maps()->max_top, dt = 2.0f;
  for (uint32_t j = 1; j < kTexels; j += 3)
    for (uint32_t i = 1; i < kTexels; i += 3) {
      const glm::vec2 xz = map.origin + (glm::vec2(i, j) + 0.5f) / float(kTexels) * map.size;
      const glm::vec3 q(xz.x, map.height, xz.y);
      const size_t first = points.size();
      for (float t = (top - q.y) / l.y - 0.5f * dt; t > 0.0f; t -= dt) {
        const glm::vec3 p = q + l * t;
        if (p.y < hill(p.x, p.z)) break;
        points.push_back(p);
      }
      spans.emplace_back(first, points.size());
      texels.push_back(size_t(j) * kTexels + i);
    }
  const std::vector<glm::vec4> density = layer_->probe(draw, m, in, points);
  double err = 0.0, worst = 0.0;
  int shadowed = 0, clear = 0;
  for (size_t k = 0; k < texels.size(); ++k) {
    double od = 0.0;
    for (size_t i = spans[k].first; i < spans[k].second; ++i) od += density[i].x * dt;
    const double cpu = std::exp(-od * in.settings.extinction);
    const double e = std::abs(cpu - gpu[texels[k]]);
    err += e, worst = std::max(worst, e);
    if (cpu < 0.5) ++shadowed;
    if (cpu > 0.999) ++clear;
  }
  err /= double(texels.size());
  std::printf("envelope shadow: %zu texels, %d in shadow (T < 0.5), %d clear; |GPU - CPU| mean %.4f, worst %.4f\n",
              texels.size(), shadowed, clear, err, worst);
  EXPECT_GT(shadowed, 10);
  EXPECT_GT(clear, 10);
  EXPECT_LT(err, 0.02);
  EXPECT_LT(worst, 0.15);

  // Folded into a voxel clouds' map (0.5 everywhere, on a plane 800 m up): 0.5 x the envelope's where it covers.
  const uint16_t half = 0x3800;  // 0.5
  const std::vector<uint16_t> halves(16, half);
  gpu::Image voxel_img(ctx(), gpu::ImageDesc::tex2d(4, 4, VK_FORMAT_R16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "test.voxel_shadow"));
  voxel_img.upload({{halves.data(), halves.size() * 2}});
  RenderGraph g2({width_, height_});
  LightShadowMap voxel;
  voxel.texture = g2.import_texture("test.voxel_shadow", TextureDesc::absolute(VK_FORMAT_R16_SFLOAT, 4, 4), voxel_img.handle(),
                                    voxel_img.view(), ResourceState::shader_read_only());
  voxel.origin = glm::vec2(-3000.0f, -3000.0f);
  voxel.size = glm::vec2(3000.0f);  // the quarter x, z < 0 on its plane
  voxel.height = 800.0f;
  const LightShadowMap both = layer_->add_shadow_passes(g2, draw, m, in, voxel);
  ASSERT_TRUE(both.texture.valid());
  EXPECT_LE(both.height, map.height);
  const std::vector<float> combined = read_r16f(g2, both.texture, kTexels);
  int checked_half = 0, checked_env = 0;
  for (uint32_t j = 0; j < kTexels; ++j)
    for (uint32_t i = 0; i < kTexels; ++i) {
      const glm::vec2 xz = both.origin + (glm::vec2(i, j) + 0.5f) / float(kTexels) * both.size;
      const glm::vec2 on_voxel = xz + glm::vec2(l.x, l.z) * ((voxel.height - both.height) / l.y);
      const bool in_voxel = on_voxel.x > -2990.0f && on_voxel.x < -10.0f && on_voxel.y > -2990.0f && on_voxel.y < -10.0f;
      const bool out_voxel = on_voxel.x > 10.0f || on_voxel.y > 10.0f;
      const glm::vec2 uv = (xz - map.origin) / map.size * float(kTexels) - 0.5f;
      const bool outside_env = uv.x < -1.0f || uv.y < -1.0f || uv.x > kTexels || uv.y > kTexels;
      if (in_voxel && outside_env) {
        EXPECT_NEAR(combined[size_t(j) * kTexels + i], 0.5f, 2e-3f);
        ++checked_half;
      } else if (out_voxel && !outside_env && uv.x > 1 && uv.y > 1 && uv.x < kTexels - 2 && uv.y < kTexels - 2) {
        // Bilinear in the envelope's map: within its neighbours' range.
        const int x0 = int(uv.x), y0 = int(uv.y);
        float lo = 1.0f, hi = 0.0f;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const float v = gpu[size_t(y0 + dy) * kTexels + size_t(x0 + dx)];
            lo = std::min(lo, v), hi = std::max(hi, v);
          }
        EXPECT_GE(combined[size_t(j) * kTexels + i], lo - 2e-3f);
        EXPECT_LE(combined[size_t(j) * kTexels + i], hi + 2e-3f);
        ++checked_env;
      }
    }
  EXPECT_GT(checked_half, 50);
  EXPECT_GT(checked_env, 50);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// The path tracer traces the envelope's clouds (reference_trace.comp ENVELOPE): the view rays' transmittance, a
// ratio-tracking estimate through the same density, is the real-time march's, under the majorant everywhere.
TEST_F(EnvelopeLayerTest, ThePathTracerTracesTheSameEnvelope) {
  using namespace cumulo::render;
  set_size(48, 27);
  const scene::CameraView cam = camera({700.0f, 1200.0f, 900.0f}, {0.0f, 300.0f, 0.0f}, 60.0f);
  CloudFrameInputs in = env_inputs(cam);
  EnvelopeDraw draw;
  draw.maps = test_maps();
  EnvelopeMarchSettings m;
  m.max_steps = 4096;
  m.step_m = 2.0f, m.step_growth = 0.0f;  // fine steps: the march's own error well under the estimate's noise
  const Frame rt = march(cam, true, m);
  ReferenceTracer tracer(ctx(), *library_);
  tracer.settings().max_bounces = 4;
  tracer.settings().samples_per_frame = 16;
  tracer.settings().uniform_sky = 0.5f;
  tracer.reset();
  const ReferenceImage img = trace(tracer, in, draw, m, 2);
  ASSERT_TRUE(in.envelope_medium.valid());
  ASSERT_EQ(img.radiance.size(), rt.color.size());
  double diff = 0.0, cover = 0.0, lit = 0.0;
  for (size_t i = 0; i < rt.color.size(); ++i) {
    const double a_rt = 1.0 - rt.color[i].a;
    diff += std::abs(a_rt - img.radiance[i].a);
    cover += a_rt;
    if (a_rt > 0.9) lit += img.radiance[i].r + img.radiance[i].g + img.radiance[i].b;
  }
  diff /= double(rt.color.size());
  cover /= double(rt.color.size());
  std::printf("envelope traced: cloud cover %.3f, |opacity reference - march| mean %.4f, majorant violations %.0f\n", cover,
              diff, img.majorant_violations);
  EXPECT_GT(cover, 0.05);
  EXPECT_LT(diff, 0.03);
  EXPECT_EQ(img.majorant_violations, 0.0);
  EXPECT_GT(lit, 0.0);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// Issue 21: with the slab presets the envelope is lit by Wrenninge's octaves and the slab's sky (envelope_march.comp
// octave_light); issue 24's terms stay with the talk's preset. Against the path tracer on the same envelope under a
// uniform sky of the march's ambient radiance over a black ground, multiple scattering included, from the lit side
// and backlit. (On the sample level's envelope views the octaves measured nearer the reference than issue 24's terms;
// on this synthetic scene they are not: backlit here 30 % against 21 %. docs/fidelity/envelope_lighting.md.)
TEST_F(EnvelopeLayerTest, TheSlabPresetsOctavesLightTheEnvelopeWithinAThirdOfThePathTracer) {
  using namespace cumulo::render;
  set_size(48, 27);
  const float sky = 0.5f;
  EnvelopeDraw draw;
  draw.maps = test_maps();
  EnvelopeMarchSettings m;
  m.max_steps = 4096;
  m.step_m = 2.0f, m.step_growth = 0.0f;
  const scene::CameraView views[2] = {camera({700.0f, 1200.0f, 900.0f}, {0.0f, 300.0f, 0.0f}, 60.0f),     // the lit side
                                      camera({-1400.0f, 250.0f, 1000.0f}, {0.0f, 400.0f, 0.0f}, 60.0f)};  // backlit
  for (const scene::CameraView& cam : views) {
    auto inputs = [&](CloudLightingPreset preset) {
      CloudFrameInputs in = env_inputs(cam);
      in.ambient_color = glm::vec3(sky);
      apply_lighting_preset(in.settings, preset);
      in.settings.ground_albedo = 0.0f;  // the traced scene has no ground to bounce light
      return in;
    };
    const std::vector<glm::vec4> octaves = march_with(cam, m, inputs(CloudLightingPreset::Slab)).color;
    const std::vector<glm::vec4> issue24 = march_with(cam, m, inputs(CloudLightingPreset::Talk)).color;
    ReferenceTracer tracer(ctx(), *library_);
    tracer.settings().max_bounces = 32;
    tracer.settings().samples_per_frame = 16;
    tracer.settings().uniform_sky = sky;
    tracer.settings().uniform_sky_upper_only = true;  // black below the horizon
    tracer.reset();
    CloudFrameInputs in = inputs(CloudLightingPreset::Slab);
    const ReferenceImage img = trace(tracer, in, draw, m, 6);
    ASSERT_EQ(img.radiance.size(), octaves.size());
    auto lum = [](glm::vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
    // The march's colour is the cloud's radiance and its transmittance; the tracer's includes what lies behind (the sky
    // above the horizon, black below), which the march's gets too. Compared where the cloud is nearly opaque.
    double err_oct = 0.0, err_24 = 0.0, ref_sum = 0.0, oct_sum = 0.0, n = 0.0;
    for (uint32_t y = 0; y < height_; ++y)
      for (uint32_t x = 0; x < width_; ++x) {
        const size_t i = size_t(y) * width_ + x;
        if (img.radiance[i].a < 0.8) continue;
        const glm::vec2 ndc((x + 0.5f) / width_ * 2.0f - 1.0f, (y + 0.5f) / height_ * 2.0f - 1.0f);
        const glm::vec4 w = cam.inv_view_proj * glm::vec4(ndc, 0.5f, 1.0f);
        const float behind = (glm::vec3(w) / w.w).y > cam.position.y ? sky : 0.0f;  // the pixel's ray up or down
        const double r = lum(glm::vec3(img.radiance[i]));
        const double o = lum(glm::vec3(octaves[i])) + behind * octaves[i].a, t = lum(glm::vec3(issue24[i])) + behind * issue24[i].a;
        err_oct += std::abs(o - r) / r, err_24 += std::abs(t - r) / r;
        ref_sum += r, oct_sum += o, n += 1.0;
      }
    EXPECT_GT(n, 50.0);
    err_oct /= n, err_24 /= n;
    std::printf("envelope lighting against the path tracer (%.0f pixels): octaves %.1f %% (mean %.3f, reference %.3f), "
                "issue 24's %.1f %%\n", n, 100.0 * err_oct, oct_sum / n, ref_sum / n, 100.0 * err_24);
    // The octaves' eccentricity is calibrated on the sample level's envelope views (session 57: c 0.5, with the light
    // samples eroded as the view ray's density and the orders past the first darkened at the edges); under this uniform
    // sky over a black ground the lit side comes out 23 % under (34 % before those, at c 0.7), the backlit 26 % off.
    EXPECT_LT(err_oct, 0.35);
    EXPECT_NEAR(oct_sum / ref_sum, 1.0, 0.36);
    EXPECT_GT(std::abs(err_oct - err_24), 0.001);  // the two presets light it differently
  }
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// Issue 21: past the first order the envelope's sun light is at least diffusion's through the optical depth toward the
// sun (envelope_ms_diffused): a thick bank passes far more of it than the octaves' exp(-a^n od). The floor only adds light
// (no pixel darker), adds it where the bank is thick toward the sun (backlit under a low sun), far less where the sun's
// path through it is short (the lit side), and 0 is the octaves alone. (Calibrated on the
// sample level's envelope views against the path tracer: docs/fidelity/envelope_lighting.md, "Session 53".)
TEST_F(EnvelopeLayerTest, TheDiffusedFloorPassesAThickBanksLightWhereTheOctavesFallOff) {
  using namespace cumulo::render;
  set_size(48, 27);
  EnvelopeDraw draw;
  draw.maps = test_maps();
  EnvelopeMarchSettings m;
  m.max_steps = 4096;
  m.step_m = 2.0f, m.step_growth = 0.0f;
  // A low sun beyond the bank from the backlit camera, behind the lit one.
  const glm::vec3 l = glm::normalize(glm::vec3(1.4f, 0.3f, -1.0f));
  const scene::CameraView backlit = camera({-1400.0f, 250.0f, 1000.0f}, {0.0f, 400.0f, 0.0f}, 60.0f);
  const scene::CameraView lit = camera(glm::vec3(0.0f, 400.0f, 0.0f) + 1700.0f * l, {0.0f, 400.0f, 0.0f}, 60.0f);
  auto inputs = [&](const scene::CameraView& cam, float diffused) {
    CloudFrameInputs in = env_inputs(cam);
    in.sun_direction = l;
    apply_lighting_preset(in.settings, CloudLightingPreset::Slab);
    if (diffused >= 0.0f) in.settings.envelope_ms_diffused = diffused;
    return in;
  };
  EXPECT_GT(inputs(lit, -1.0f).settings.envelope_ms_diffused, 0.0f);  // the slab preset has the floor
  auto lum = [](glm::vec4 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  double gain[2] = {0.0, 0.0};
  for (int v = 0; v < 2; ++v) {
    const scene::CameraView& cam = v == 0 ? backlit : lit;
    const std::vector<glm::vec4> with = march_with(cam, m, inputs(cam, -1.0f)).color;
    const std::vector<glm::vec4> without = march_with(cam, m, inputs(cam, 0.0f)).color;
    ASSERT_EQ(with.size(), without.size());
    double sum_with = 0.0, sum_without = 0.0;
    int darker = 0, cloud = 0;
    for (size_t i = 0; i < with.size(); ++i) {
      if (lum(with[i]) < lum(without[i]) - 1e-5) ++darker;
      if (without[i].a > 0.2) continue;  // nearly opaque cloud
      sum_with += lum(with[i]), sum_without += lum(without[i]), ++cloud;
    }
    ASSERT_GT(cloud, 20);
    gain[v] = sum_with / sum_without - 1.0;
    std::printf("%s: the diffused floor adds %.1f %% over %d cloud pixels\n", v == 0 ? "backlit" : "lit side", 100.0 * gain[v],
                cloud);
    EXPECT_EQ(darker, 0);
  }
  // Session 57: the eroded light samples pass more light through the octaves themselves, so the floor adds less (4.7 %;
  // more than 5 % before).
  EXPECT_GT(gain[0], 0.03);
  EXPECT_LT(gain[1], 0.5 * gain[0]);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// Issue 21, session 57: the view ray's density is eroded by the detail noise, the light samples toward the sun skip it
// (a fetch each), so they saw more cloud than the ray: with the slab presets they erode by the detail's mean fBm. That
// only takes optical depth away (no pixel darker), lights the cloud seen against the sun more than its lit side, and is
// off in the talk's preset (which the switch does not touch).
TEST_F(EnvelopeLayerTest, TheSlabLightSamplesSeeTheErodedCloudTheViewRaySees) {
  using namespace cumulo::render;
  set_size(48, 27);
  EnvelopeMarchSettings m;
  m.max_steps = 4096;
  m.step_m = 2.0f, m.step_growth = 0.0f;
  ASSERT_GT(m.detail_erosion, 0.0f);
  const glm::vec3 l = glm::normalize(glm::vec3(1.4f, 0.3f, -1.0f));
  const scene::CameraView backlit = camera({-1400.0f, 250.0f, 1000.0f}, {0.0f, 400.0f, 0.0f}, 60.0f);
  const scene::CameraView lit = camera(glm::vec3(0.0f, 400.0f, 0.0f) + 1700.0f * l, {0.0f, 400.0f, 0.0f}, 60.0f);
  auto inputs = [&](const scene::CameraView& cam, CloudLightingPreset preset, bool erosion) {
    CloudFrameInputs in = env_inputs(cam);
    in.sun_direction = l;
    apply_lighting_preset(in.settings, preset);
    in.settings.envelope_light_erosion = erosion;
    return in;
  };
  EXPECT_TRUE(inputs(lit, CloudLightingPreset::Slab, true).settings.envelope_light_erosion);
  {
    CloudSettings talk;
    apply_lighting_preset(talk, CloudLightingPreset::Talk);
    EXPECT_FALSE(talk.envelope_light_erosion);
    CloudSettings slab;
    apply_lighting_preset(slab, CloudLightingPreset::Slab);
    EXPECT_TRUE(slab.envelope_light_erosion);
  }
  auto lum = [](glm::vec4 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  double gain[2] = {0.0, 0.0};
  for (int v = 0; v < 2; ++v) {
    const scene::CameraView& cam = v == 0 ? backlit : lit;
    const std::vector<glm::vec4> on = march_with(cam, m, inputs(cam, CloudLightingPreset::Slab, true)).color;
    const std::vector<glm::vec4> off = march_with(cam, m, inputs(cam, CloudLightingPreset::Slab, false)).color;
    ASSERT_EQ(on.size(), off.size());
    double sum_on = 0.0, sum_off = 0.0;
    int darker = 0, cloud = 0;
    for (size_t i = 0; i < on.size(); ++i) {
      EXPECT_EQ(on[i].a, off[i].a) << i;  // the view ray's density is the same
      if (lum(on[i]) < lum(off[i]) - 1e-5) ++darker;
      if (off[i].a > 0.2) continue;  // nearly opaque cloud
      sum_on += lum(on[i]), sum_off += lum(off[i]), ++cloud;
    }
    ASSERT_GT(cloud, 20);
    gain[v] = sum_on / sum_off - 1.0;
    std::printf("%s: the eroded light samples add %.1f %% over %d cloud pixels\n", v == 0 ? "backlit" : "lit side",
                100.0 * gain[v], cloud);
    EXPECT_EQ(darker, 0);
  }
  EXPECT_GT(gain[0], 0.02);
  EXPECT_GT(gain[0], gain[1]);
  // The talk's preset: the switch changes nothing.
  const std::vector<glm::vec4> talk_on = march_with(backlit, m, inputs(backlit, CloudLightingPreset::Talk, true)).color;
  const std::vector<glm::vec4> talk_off = march_with(backlit, m, inputs(backlit, CloudLightingPreset::Talk, false)).color;
  ASSERT_EQ(talk_on.size(), talk_off.size());
  for (size_t i = 0; i < talk_on.size(); ++i) EXPECT_EQ(glm::vec3(talk_on[i]), glm::vec3(talk_off[i])) << i;
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// The detail noise's mean fBm, as envelope_density.glsl weighs its channels (0.625, 0.25, 0.125; A unused).
TEST(EnvelopeDetailMeanFbm, WeighsTheChannelsAsTheDensityDoes) {
  Volume v = Volume::create(glm::uvec3(2, 1, 1), 1.0f, VolumeEncoding::RGBA8,
                            {{"r"}, {"g"}, {"b"}, {"a"}});
  v.levels[0] = {255, 0, 0, 255, 0, 255, 255, 0};
  EXPECT_NEAR(detail_mean_fbm(v), (0.625 + 0.375) / 2.0, 1e-6);
  v.levels[0] = {102, 102, 102, 9, 102, 102, 102, 200};
  EXPECT_NEAR(detail_mean_fbm(v), 0.4, 1e-6);
  EXPECT_EQ(detail_mean_fbm(Volume{}), 0.0f);
}

// The sun's light on the envelope goes through what lies between: the voxel clouds above (their shadow map, on its
// plane under their boxes, read where the sample's ray toward the sun crosses it) and the terrain (the light's depth
// map). Issue 21: the path tracer showed the sample level's bank in the hero cloud's shadow where the march lit it.
TEST_F(EnvelopeLayerTest, TheVoxelCloudsAndTheTerrainHideTheSunFromTheEnvelope) {
  using namespace cumulo::render;
  set_size(96, 54);
  const scene::CameraView cam = camera({700.0f, 1200.0f, 900.0f}, {0.0f, 300.0f, 0.0f}, 60.0f);
  EnvelopeMarchSettings m;
  m.max_steps = 4096;
  const CloudFrameInputs in = env_inputs(cam);
  const glm::vec3 l = glm::normalize(in.sun_direction);
  constexpr uint32_t kTexels = 64;
  constexpr float kPlane = 800.0f;  // the voxel clouds' map: world y
  // Its halves meet where the light from the cap's middle (x = 0 at 300 m) crosses the plane.
  const float split = l.x * (kPlane - 300.0f) / l.y;
  auto voxel_map = [&](float left, float right) {  // transmittance for plane x < split and x >= split
    std::vector<float> v(kTexels * kTexels);
    for (uint32_t j = 0; j < kTexels; ++j)
      for (uint32_t i = 0; i < kTexels; ++i) v[j * kTexels + i] = i < kTexels / 2 ? left : right;
    return float_image(kTexels, VK_FORMAT_R16_SFLOAT, v, "test.voxel_shadow");
  };
  auto with_voxel = [&](const gpu::Image& img) {
    before_march_ = [&img, split](RenderGraph& g, CloudFrameInputs& i) {
      i.voxel_shadow.texture = g.import_texture("test.voxel_shadow", TextureDesc::absolute(VK_FORMAT_R16_SFLOAT, kTexels, kTexels),
                                                img.handle(), img.view(), ResourceState::shader_read_only());
      i.voxel_shadow.origin = glm::vec2(split - 3000.0f, -3000.0f);
      i.voxel_shadow.size = glm::vec2(6000.0f);
      i.voxel_shadow.height = kPlane;
    };
    return march_with(cam, m, in).color;
  };
  // The terrain's depth from the light: every texel's occluder at the light's side (0: all in shadow) or the far side.
  auto with_terrain = [&](float occluder) {
    const gpu::Image img = float_image(2, VK_FORMAT_R32_SFLOAT, std::vector<float>(4, occluder), "test.light_depth");
    before_march_ = [&img, l](RenderGraph& g, CloudFrameInputs& i) {
      i.terrain_depth = g.import_texture("test.light_depth", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, 2, 2), img.handle(),
                                         img.view(), ResourceState::shader_read_only());
      i.terrain_depth_matrix = glm::orthoRH_ZO(-3000.0f, 3000.0f, -3000.0f, 3000.0f, 0.0f, 10000.0f) *
                               glm::lookAt(l * 5000.0f, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f));
      i.terrain_depth_range_m = 10000.0f;
    };
    return march_with(cam, m, in).color;
  };
  before_march_ = nullptr;
  const Frame lit_frame = march_with(cam, m, in);
  const std::vector<glm::vec4>& lit = lit_frame.color;
  const std::vector<glm::vec4> clear = with_voxel(voxel_map(1.0f, 1.0f));
  const std::vector<glm::vec4> dark = with_voxel(voxel_map(0.0f, 0.0f));
  const std::vector<glm::vec4> half = with_voxel(voxel_map(0.0f, 1.0f));
  const std::vector<glm::vec4> terrain_far = with_terrain(1.0f);
  const std::vector<glm::vec4> terrain_hides = with_terrain(0.0f);
  before_march_ = nullptr;

  auto lum = [](const glm::vec4& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  double lit_sum = 0.0, dark_sum = 0.0, worst_clear = 0.0, worst_far = 0.0, worst_hidden = 0.0;
  int cloud = 0, in_shadow = 0, in_light = 0, half_bad = 0;
  for (size_t i = 0; i < lit.size(); ++i) {
    if (lit[i].a > 0.5) continue;  // mostly cloud
    ++cloud;
    const double L = lum(lit[i]), D = lum(dark[i]);
    lit_sum += L, dark_sum += D;
    worst_clear = std::max(worst_clear, std::abs(lum(clear[i]) - L) / L);
    worst_far = std::max(worst_far, std::abs(lum(terrain_far[i]) - L) / L);
    worst_hidden = std::max(worst_hidden, std::abs(lum(terrain_hides[i]) - D) / std::max(D, 1e-3));
  }
  // The half map: where a cloud's rays toward the sun cross the plane well inside one half (from where its pixel turns
  // opaque), that half's picture.
  for (uint32_t y = 0; y < height_; ++y)
    for (uint32_t x = 0; x < width_; ++x) {
      const size_t i = size_t(y) * width_ + x;
      if (lit[i].a > 0.5 || lit_frame.depth[i].x > 1e5f) continue;
      const glm::vec2 ndc((x + 0.5f) / width_ * 2.0f - 1.0f, (y + 0.5f) / height_ * 2.0f - 1.0f);
      const glm::vec4 w = cam.inv_view_proj * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 rd = glm::normalize(glm::vec3(w) / w.w - cam.position);
      const glm::vec3 p = cam.position + rd * lit_frame.depth[i].x;
      const float plane_x = p.x + l.x * (kPlane - p.y) / l.y;
      const double H = lum(half[i]), L = lum(lit[i]), D = lum(dark[i]);
      if (plane_x < split - 150.0f) {
        ++in_shadow;
        if (std::abs(H - D) > 0.1 * std::abs(L - D) + 1e-3) ++half_bad;
      } else if (plane_x > split + 150.0f) {
        ++in_light;
        if (std::abs(H - L) > 0.1 * std::abs(L - D) + 1e-3) ++half_bad;
      }
    }
  std::printf("envelope under the voxel clouds' shadow: %d cloud pixels, luminance %.3f lit, %.3f under T = 0; a map of 1 "
              "changes it by %.2e at most, the terrain's far side by %.2e, the terrain hiding the sun differs from T = 0 by "
              "%.2e; half map: %d pixels in its shadow, %d in its light, %d off\n",
              cloud, lit_sum / std::max(cloud, 1), dark_sum / std::max(cloud, 1), worst_clear, worst_far, worst_hidden,
              in_shadow, in_light, half_bad);
  ASSERT_GT(cloud, 200);
  EXPECT_LT(dark_sum, 0.8 * lit_sum);  // the sun is most of an envelope cloud's light from above
  EXPECT_GT(dark_sum, 0.02 * lit_sum);  // the sky's is left
  EXPECT_LT(worst_clear, 2e-3);
  EXPECT_LT(worst_far, 2e-3);
  EXPECT_LT(worst_hidden, 2e-3);
  EXPECT_GT(in_shadow, 30);
  EXPECT_GT(in_light, 30);
  EXPECT_LE(half_bad, (in_shadow + in_light) / 20);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

}  // namespace
}  // namespace cumulo::clouds::render::test
