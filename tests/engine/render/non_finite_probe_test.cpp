// render::NonFiniteProbe (the soak's check that a frame holds no NaN or infinity, counted on the GPU): frames whose
// scene colour a test feature spoils with NaNs or infinities are counted, with their texels; clean frames are not.
#include "engine/render/non_finite_probe.h"

#include <gtest/gtest.h>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/pass_helpers.h"
#include "engine/render/sky_model.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf.h"
#include "engine/scene/sun.h"
#include "tests/support/render_offscreen.h"

namespace cumulo {
namespace {

// Writes `bits` (as a float) into the first `count` texels of the scene colour after the opaque geometry.
struct Spoiler : render::RenderFeature {
  gpu::Pipeline* pipe = nullptr;
  gpu::Context* ctx = nullptr;
  uint32_t bits = 0;
  int count = 0;
  void create_gpu(render::GpuServices& g) override {
    ctx = &g.ctx;
    pipe = &g.library.compute({.shader = "test/write_non_finite.comp", .name = "test write non-finite"});
  }
  void add_passes(render::Stage stage, render::StageContext& f) override {
    using namespace render;
    if (stage != Stage::AfterOpaque || count == 0) return;
    struct Push {
      uint32_t bits;
      int32_t count;
    } push{bits, count};
    f.graph.add_pass("test spoil", Queue::Compute,
        [&](PassBuilder& b) { f.hdr = b.read_write(f.hdr, Usage::StorageWrite); },
        [this, push, hdr = f.hdr](PassContext& c) {
          pipe->bind(c.cmd());
          gpu::DescriptorWriter().storage_image(0, c.view(hdr)).push(*ctx, c.cmd(), *pipe);
          pipe->push_constants(c.cmd(), push);
          vkCmdDispatch(c.cmd(), 1, 1, 1);
        });
  }
};

TEST(NonFiniteProbe, CountsTheFramesAndTexelsThatHoldANanOrAnInfinity) {
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  Spoiler spoiler;
  render::NonFiniteProbe probe;
  {
    render::FrameRenderer renderer(ctx);
    renderer.add_feature(spoiler);
    renderer.add_feature(probe);  // after it: sees what it wrote
    render::FrameSnapshot s;
    s.width = 64;
    s.height = 36;
    scene::TimeOfDay tod;
    tod.hours = 12.0f;
    s.sun = scene::sun_light(tod, scene::Sun{});
    s.lighting = render::sky_lighting(s.sun);
    s.camera = scene::make_camera_view(scene::Transform::look_at({0, 10, 0}, {0, 60, -100}), scene::Camera{}, 64.0f / 36.0f);
    auto frame = [&](uint32_t bits, int count) {
      spoiler.bits = bits;
      spoiler.count = count;
      test::render_offscreen(ctx, renderer, s);
      return probe.counts();
    };
    EXPECT_EQ(frame(0, 0).bad_frames, 0u);                // a clean frame
    EXPECT_EQ(frame(0x3f800000u, 5).bad_frames, 0u);      // 1.0: finite
    render::NonFiniteProbe::Counts c = frame(0x7fc00000u, 3);  // quiet NaN in 3 texels
    EXPECT_EQ(c.bad_frames, 1u);
    EXPECT_EQ(c.bad_pixels, 3u);
    c = frame(0x7f800000u, 7);  // +infinity in 7 texels
    EXPECT_EQ(c.bad_frames, 2u);
    EXPECT_EQ(c.bad_pixels, 10u);
    EXPECT_EQ(c.last_bad_pixel, glm::ivec2(0, 0));  // the first of the row it wrote
    c = frame(0, 0);
    EXPECT_EQ(c.frames, 5u);
    EXPECT_EQ(c.bad_frames, 2u);
    EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  }
}

// The soak found one NaN pixel a lap on the ocean where the camera looked straight away from the sun: the glint's
// Schlick term took pow(1 - dot(v, h), 5) of two unit vectors whose dot rounded past 1. A camera with a narrow
// field of view centred on the antisolar point puts thousands of pixels within a rounding of it.
TEST(NonFiniteProbe, TheOceanHoldsNoNanWhereTheCameraLooksAwayFromTheSun) {
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  auto terrain = std::make_shared<const scene::Model>(scene::load_gltf("content/levels/sample/terrain.glb"));
  render::NonFiniteProbe probe;
  {
    render::FrameRenderer renderer(ctx);
    renderer.add_feature(probe);
    uint64_t frames = 0;
    for (float hours : {9.0f, 10.5f, 15.0f}) {
      render::FrameSnapshot s;
      s.width = 64;
      s.height = 36;
      scene::TimeOfDay tod;
      tod.hours = hours;
      s.sun = scene::sun_light(tod, scene::Sun{});
      s.lighting = render::sky_lighting(s.sun);
      s.models.push_back({terrain, glm::mat4(1.0f)});
      // Over open water 1.5 km south-east of the islands, looking down along the sun's direction.
      const glm::vec3 at(2150.0f, 0.0f, 2200.0f);
      const glm::vec3 eye = at + s.sun.direction * 1500.0f / s.sun.direction.y;
      scene::Camera narrow;
      narrow.fov_y_deg = 0.05f;
      s.camera = scene::make_camera_view(scene::Transform::look_at(eye, at), narrow, 64.0f / 36.0f);
      test::render_offscreen(ctx, renderer, s);
      ++frames;
      const render::NonFiniteProbe::Counts c = probe.counts();
      EXPECT_EQ(c.frames, frames);
      EXPECT_EQ(c.bad_pixels, 0u) << hours << " h: the first at (" << c.last_bad_pixel.x << ", " << c.last_bad_pixel.y << ")";
    }
    EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  }
}

}  // namespace
}  // namespace cumulo
