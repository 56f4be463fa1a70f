// The atmosphere's LUT passes on the device (lavapipe on CI) against the CPU model they mirror: the
// sky-view LUT's texels (the sun 10 degrees up, the camera at 10 m) agree with Atmosphere::sky_radiance in
// the same directions within 10 % where the sky is brighter than 1 % of the zenith's, with zero validation
// errors; a second frame with the same sun does not recompute the LUTs. The aerial-perspective froxels
// against Atmosphere::aerial_perspective the same way.
#include "engine/render/atmosphere/atmosphere_passes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/readback.h"
#include "engine/render/graph/executor.h"
#include "engine/render/sky_model.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

glm::vec3 sky_view_dir(glm::vec2 uv, glm::vec3 sun) {  // atmosphere_common.glsl's atm_sky_view_dir
  const float pi = 3.14159265358979f;
  const float s = uv.y * 2.0f - 1.0f;
  const float e = (s < 0.0f ? -1.0f : 1.0f) * s * s * 0.5f * pi;
  const float az = uv.x * 2.0f * pi + std::atan2(sun.z, sun.x);
  return {std::cos(e) * std::cos(az), std::sin(e), std::cos(e) * std::sin(az)};
}

// Copies `tex` into `buffer` at the end of `g` (a host-read buffer the test downloads after the submit).
void add_readback(RenderGraph& g, TextureHandle tex, const gpu::Buffer& buffer) {
  BufferHandle buf = g.import_buffer("readback", buffer.handle(), buffer.size(), ResourceState::host_read(),
                                     ResourceState::host_read());
  g.add_pass("readback", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(tex, Usage::TransferSrc);
        buf = b.write(buf, Usage::TransferDst);
        b.side_effect();
      },
      [tex, buf](PassContext& c) {
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = c.extent(tex);
        vkCmdCopyImageToBuffer(c.cmd(), c.image(tex), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(buf), 1, &region);
      });
}

TEST(AtmosphereGpu, SkyViewLutAgreesWithTheCpuModel) {
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  gpu::PipelineLibrary library(ctx);
  const Atmosphere& atm = default_atmosphere();
  AtmospherePasses passes(ctx, library, atm);
  FrameSnapshot s;
  const float e = glm::radians(10.0f);
  s.sun.direction = glm::vec3(0.3f * std::cos(e), std::sin(e), -0.954f * std::cos(e));
  s.sun.direction = glm::normalize(s.sun.direction);
  s.sun.elevation_deg = 10.0f;
  s.camera.position = glm::vec3(0.0f, 10.0f, 0.0f);

  const size_t texels = size_t(ATMOSPHERE_SKY_VIEW_W) * ATMOSPHERE_SKY_VIEW_H;
  gpu::Buffer readback(ctx, {texels * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "sky view readback"});
  Executor executor(ctx);
  for (int frame = 0; frame < 2; ++frame) {
    RenderGraph g({16, 16});
    const AtmosphereLuts luts = passes.add_passes(g, s, uint32_t(frame));
    add_readback(g, luts.sky_view, readback);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
  }
  EXPECT_EQ(passes.sky_view_updates(), 1u);  // the second frame kept the LUT
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();

  std::vector<uint16_t> half(texels * 4);
  readback.download(half.data(), half.size() * sizeof(uint16_t));
  const glm::vec3 sun = glm::normalize(s.sun.direction);
  const float E = atm.params().solar_irradiance;
  const float zenith = atm.sky_radiance(0.01f, {0, 1, 0}, sun, E).b;
  int checked = 0, bad = 0;
  float worst = 0.0f;
  for (int y = 2; y < ATMOSPHERE_SKY_VIEW_H; y += 7)
    for (int x = 1; x < ATMOSPHERE_SKY_VIEW_W; x += 11) {
      const glm::vec2 uv((float(x) + 0.5f) / ATMOSPHERE_SKY_VIEW_W, (float(y) + 0.5f) / ATMOSPHERE_SKY_VIEW_H);
      const glm::vec3 dir = sky_view_dir(uv, sun);
      const glm::vec3 want = atm.sky_radiance(0.01f, dir, sun, E) + Atmosphere::kAirglow * glm::vec3(1.0f, 1.2f, 2.0f);
      const size_t i = (size_t(y) * ATMOSPHERE_SKY_VIEW_W + x) * 4;
      const glm::vec3 got(gpu::half_to_float(half[i]), gpu::half_to_float(half[i + 1]), gpu::half_to_float(half[i + 2]));
      for (int c = 0; c < 3; ++c) {
        if (want[c] < 0.01f * zenith) continue;
        const float rel = std::abs(got[c] - want[c]) / want[c];
        worst = std::max(worst, rel);
        ++checked;
        bad += rel > 0.10f;
      }
    }
  std::printf("  %d texel channels checked, worst relative difference %.3f, %d above 10 %%\n", checked, worst, bad);
  EXPECT_GT(checked, 300);
  EXPECT_EQ(bad, 0);
}

// The aerial-perspective froxels (camera at 10 m looking north-east over the sea, the sun 10 degrees up)
// against Atmosphere::aerial_perspective along the same rays to each slice's end (above the ground): the in-scattering within
// 10 % where it is above 1 % of the far slices', the transmittance within 0.02.
TEST(AtmosphereGpu, AerialPerspectiveFroxelsAgreeWithTheCpuModel) {
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  gpu::PipelineLibrary library(ctx);
  const Atmosphere& atm = default_atmosphere();
  AtmospherePasses passes(ctx, library, atm);
  FrameSnapshot s;
  const float e = glm::radians(10.0f);
  s.sun.direction = glm::normalize(glm::vec3(0.3f * std::cos(e), std::sin(e), -0.954f * std::cos(e)));
  s.sun.elevation_deg = 10.0f;
  scene::Camera cam;
  s.camera = scene::make_camera_view(scene::Transform::look_at({0, 10, 0}, {700, 60, -700}), cam, 16.0f / 9.0f);
  constexpr int N = ATMOSPHERE_AERIAL_SIZE;
  const size_t texels = size_t(N) * N * N;
  gpu::Buffer readback(ctx, {texels * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "aerial readback"});
  Executor executor(ctx);
  RenderGraph g({16, 16});
  add_readback(g, passes.add_passes(g, s, 0).aerial, readback);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  std::vector<uint16_t> half(texels * 4);
  readback.download(half.data(), half.size() * sizeof(uint16_t));
  const float E = atm.params().solar_irradiance;
  const glm::vec3 sun = s.sun.direction;
  int checked = 0, bad = 0;
  float worst = 0.0f, worst_t = 0.0f;
  for (int k = 3; k < N; k += 4)
    for (int y = 1; y < N; y += 5)
      for (int x = 2; x < N; x += 5) {
        const glm::vec2 uv((x + 0.5f) / N, (y + 0.5f) / N);
        const glm::vec3 dir = s.camera.ray_direction(uv * 2.0f - 1.0f);
        const float d_km = float(ATMOSPHERE_AERIAL_KM) * float((k + 1) * (k + 1)) / float(N * N);
        if (dir.y < 0.0f && d_km * -dir.y > 0.01f) continue;  // below the ground there (the terrain covers it)
        const Atmosphere::Inscatter want = atm.aerial_perspective(0.01f, dir, sun, E, d_km);
        const size_t i = ((size_t(k) * N + y) * N + x) * 4;
        const glm::vec4 got(gpu::half_to_float(half[i]), gpu::half_to_float(half[i + 1]), gpu::half_to_float(half[i + 2]),
                            gpu::half_to_float(half[i + 3]));
        worst_t = std::max(worst_t, std::abs(got.a - (want.transmittance.r + want.transmittance.g + want.transmittance.b) / 3.0f));
        for (int c = 0; c < 3; ++c) {
          if (want.radiance[c] < 0.01f * atm.aerial_perspective(0.01f, dir, sun, E, 32.0f).radiance[c]) continue;
          const float rel = std::abs(got[c] - want.radiance[c]) / want.radiance[c];
          worst = std::max(worst, rel);
          ++checked;
          bad += rel > 0.10f;
        }
      }
  std::printf("  %d froxel channels checked, worst relative difference %.3f, %d above 10 %%; worst transmittance error %.4f\n",
              checked, worst, bad, worst_t);
  EXPECT_GT(checked, 300);
  EXPECT_EQ(bad, 0);
  EXPECT_LT(worst_t, 0.02f);
}

// The weather's haze (SceneLighting::mie_scale) thickens the air: the LUTs are rebuilt once for a new
// step of the scale (not for a change within the step), and the far froxels' transmittance drops.
TEST(AtmosphereGpu, HazeRebuildsTheLutsOnceAndThickensTheAerialPerspective) {
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  gpu::PipelineLibrary library(ctx);
  AtmospherePasses passes(ctx, library, default_atmosphere());
  FrameSnapshot s;
  s.sun.direction = glm::normalize(glm::vec3(0.3f, 0.5f, -0.8f));
  s.sun.elevation_deg = 30.0f;
  s.camera = scene::make_camera_view(scene::Transform::look_at({0, 10, 0}, {1000, 10, 0}), scene::Camera{}, 16.0f / 9.0f);
  constexpr int N = ATMOSPHERE_AERIAL_SIZE;
  gpu::Buffer readback(ctx, {size_t(N) * N * N * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "ap"});
  Executor executor(ctx);
  auto far_transmittance = [&](float mie_scale) {
    s.lighting.mie_scale = mie_scale;
    RenderGraph g({16, 16});
    add_readback(g, passes.add_passes(g, s, 0).aerial, readback);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) { executor.execute(g, cmd); });
    std::vector<uint16_t> half(size_t(N) * N * N * 4);
    readback.download(half.data(), half.size() * sizeof(uint16_t));
    return gpu::half_to_float(half[((size_t(N - 1) * N + N / 2) * N + N / 2) * 4 + 3]);  // the view's centre, 32 km
  };
  const float clear = far_transmittance(1.0f);
  EXPECT_EQ(passes.lut_builds(), 1u);
  const float hazy = far_transmittance(4.0f);
  EXPECT_EQ(passes.lut_builds(), 2u);
  far_transmittance(4.01f);  // the same 5 % step
  EXPECT_EQ(passes.lut_builds(), 2u);
  std::printf("  transmittance to 32 km along the horizon: clear air %.3f, 4x the aerosols %.3f\n", clear, hazy);
  EXPECT_LT(hazy, clear * 0.7f);
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}

}  // namespace
