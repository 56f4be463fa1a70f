// The module mechanism end to end: a test module registers a component, a system, a snapshot
// extension, a run flag and a pass at each of the three stages; `cumulo run`'s headless loop renders
// with it (lavapipe, validation on). Also: module shaders hot-reload with the engine's, and a level
// that names a component no module registered is refused with the entity, the name and the known list.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/app/application.h"
#include "engine/app/module.h"
#include "engine/app/simulation.h"
#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/readback.h"
#include "engine/gpu/sampler.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/pass_helpers.h"
#include "engine/render/sky_model.h"
#include "engine/scene/sun.h"
#include "tests/support/render_offscreen.h"
#include "tests/support/png_read.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;

namespace {

struct Spin {
  float speed = 1.0f;
  double turns = 0.0;  // runtime state the system advances
};

// Per-frame data the module extracts (a typed snapshot extension).
struct TintFrame {
  glm::vec4 tint{1.0f};
  double turns = 0.0;
};

class TestModule : public app::Module {
 public:
  const char* name() const override { return "test"; }
  void add_run_options(ArgParser& p) override { p.option("--test-tint", "R,G,B", "tint of the test module", &tint_text_); }
  void check_run_options() override {
    if (tint_text_.empty()) return;
    if (std::sscanf(tint_text_.c_str(), "%f,%f,%f", &tint_.r, &tint_.g, &tint_.b) != 3)
      fail("--test-tint: expected R,G,B, got \"%s\"", tint_text_.c_str());
  }
  void register_components(ecs::ComponentRegistry& r) override {
    r.register_component<Spin>(
        "Spin", [](const Spin& s) { return Json{{"speed", s.speed}}; },
        [](const JsonView& v) { return Spin{v.get<float>("speed", 1.0f), 0.0}; });
  }
  void register_systems(ecs::Scheduler& s) override {
    s.add_system(ecs::Phase::Update, "spin", [](ecs::World& w, const ecs::FrameContext& f) {
      w.view<Spin>().each([&](Spin& spin) { spin.turns += spin.speed * f.dt; });
    });
  }
  void on_level_loaded(ecs::World& world, const scene::LevelInfo& level) override {
    spinners_ = 0;
    world.view<const Spin>().each([&](const Spin&) { ++spinners_; });
    level_dir_ = level.directory;
  }
  void extract(const ecs::World& world, render::FrameSnapshot& s) override {
    TintFrame t;
    t.tint = glm::vec4(tint_, 1.0f);
    world.view<const Spin>().each([&](const Spin& spin) { t.turns = spin.turns; });
    s.extensions.set(t);
  }
  void create_gpu(render::GpuServices& g) override {
    fill_ = &g.library.compute({"test/module_fill.comp", {}, "test module fill"});
    tint_pipe_ = &g.library.compute({"test/module_tint.comp", {}, "test module tint"});
    ++gpu_created_;
  }
  void destroy_gpu() override {
    overlay_.clear();
    ++gpu_destroyed_;
  }
  void add_passes(render::Stage stage, render::StageContext& f) override {
    using namespace render;
    const TintFrame& t = f.snapshot.extensions.get<TintFrame>();
    last_turns_ = t.turns;
    if (stage == Stage::BeforeScene) {
      tint_tex_ = f.graph.create_texture("test tint", TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1));
      f.graph.add_pass("test before-scene", Queue::Compute,
          [&](PassBuilder& b) { tint_tex_ = b.write(tint_tex_, Usage::StorageWrite); },
          [this, tex = tint_tex_, color = t.tint](PassContext& c) {
            fill_->bind(c.cmd());
            gpu::DescriptorWriter().storage_image(0, c.view(tex)).push(*ctx(c), c.cmd(), *fill_);
            fill_->push_constants(c.cmd(), color);
            vkCmdDispatch(c.cmd(), 1, 1, 1);
          });
      ctx_ = &f.ctx;
    } else if (stage == Stage::AfterOpaque) {
      f.graph.add_pass("test after-opaque", Queue::Compute,
          [&](PassBuilder& b) {
            b.read(tint_tex_, Usage::Sampled);
            f.hdr = b.read_write(f.hdr, Usage::StorageWrite);
          },
          [this, tex = tint_tex_, hdr = f.hdr](PassContext& c) {
            tint_pipe_->bind(c.cmd());
            gpu::DescriptorWriter()
                .storage_image(0, c.view(hdr))
                .sampled_image(1, c.view(tex), ctx(c)->samplers().get(gpu::SamplerDesc::nearest_clamp()))
                .push(*ctx(c), c.cmd(), *tint_pipe_);
            VkExtent3D e = c.extent(hdr);
            vkCmdDispatch(c.cmd(), groups(e.width, 8), groups(e.height, 8), 1);
          });
    } else {
      // The UI stage: a green square in the top-left corner of the display-referred output.
      gpu::Pipeline* overlay = overlay_pipeline(f);
      f.graph.add_pass("test after-tonemap", Queue::Graphics,
          [&](PassBuilder& b) { f.output = b.read_write(f.output, Usage::ColorAttachment); },
          [overlay, out = f.output](PassContext& c) {
            begin_rendering(c, Attachment{out, VK_ATTACHMENT_LOAD_OP_LOAD});
            VkRect2D corner{{0, 0}, {16, 16}};
            vkCmdSetScissor(c.cmd(), 0, 1, &corner);
            overlay->bind(c.cmd());
            struct {
              glm::vec4 color;
              float split_x;
            } push{{0.0f, 1.0f, 0.0f, 1.0f}, 1e9f};
            overlay->push_constants(c.cmd(), &push, sizeof push);
            vkCmdDraw(c.cmd(), 3, 1, 0, 0);
            vkCmdEndRendering(c.cmd());
          });
    }
  }

  std::string tint_text_;
  glm::vec3 tint_{1.0f, 0.0f, 0.0f};  // default: keep red only
  int spinners_ = -1, gpu_created_ = 0, gpu_destroyed_ = 0;
  double last_turns_ = 0.0;
  fs::path level_dir_;

 private:
  gpu::Context* ctx(const render::PassContext&) const { return ctx_; }
  gpu::Pipeline* overlay_pipeline(render::StageContext& f) {
    // The output format is only known per frame (swapchain or offscreen): one pipeline per format.
    VkFormat fmt = f.output_format;
    for (auto& [format, pipe] : overlay_)
      if (format == fmt) return pipe;
    gpu::GraphicsPipelineDesc d;
    d.vertex = "test/solid_color.vert";
    d.fragment = "test/solid_color.frag";
    d.color_formats = {fmt};
    d.name = "test overlay";
    overlay_.push_back({fmt, &f.library.graphics(d)});
    return overlay_.back().second;
  }
  gpu::Pipeline* fill_ = nullptr;
  gpu::Pipeline* tint_pipe_ = nullptr;
  std::vector<std::pair<VkFormat, gpu::Pipeline*>> overlay_;
  gpu::Context* ctx_ = nullptr;
  render::TextureHandle tint_tex_;
};

using test::Png;
using test::load_png;

std::vector<char*> argv_of(std::vector<std::string>& args) {
  std::vector<char*> v;
  for (auto& a : args) v.push_back(a.data());
  return v;
}

}  // namespace

TEST(Module, HeadlessRunDrivesEveryHookAndStage) {
  fs::path dir = test::unique_temp_path("cumulo_module_test");
  fs::create_directories(dir);
  auto module = std::make_shared<TestModule>();
  app::Modules modules{module};
  std::vector<std::string> args{"run", "tests/engine/app/data/module_level.json", "--headless", "--frames", "3", "--size",
                                "160x90", "--screenshot", (dir / "shot.png").string(), "--dump-graph",
                                (dir / "graph.txt").string(), "--test-tint", "1,0,0"};
  auto argv = argv_of(args);
  auto options = app::parse_run_options(int(argv.size()), argv.data(), modules);
  ASSERT_TRUE(options);
  EXPECT_EQ(app::run_level(*options, modules), 0);  // 3 would mean validation errors

  EXPECT_EQ(module->spinners_, 1);                 // on_level_loaded saw the component
  EXPECT_EQ(module->level_dir_, fs::path("tests/engine/app/data"));
  EXPECT_NEAR(module->last_turns_, 2.0 * 3.0 / 30.0, 1e-9);  // the system ran 3 frames of 1/30 s at speed 2
  EXPECT_EQ(module->gpu_created_, 1);
  EXPECT_EQ(module->gpu_destroyed_, 1);

  // The compiled graph: before-scene ahead of geometry, after-opaque between sky and tonemap,
  // after-tonemap last.
  // The dump lists "pass N NAME (queue)" in execution order.
  std::string graph = read_file_text(dir / "graph.txt");
  std::vector<std::string> order;
  for (size_t pos = graph.find("\npass "); pos != std::string::npos; pos = graph.find("\npass ", pos + 1)) {
    size_t name = graph.find(' ', pos + 6) + 1, end = graph.find(" (", name);
    order.push_back(graph.substr(name, end - name));
  }
  // (The first frame also builds the atmosphere's LUTs, before the geometry (the aerial froxels) and the sky.)
  EXPECT_EQ(order, (std::vector<std::string>{"test before-scene", "atmosphere.transmittance", "atmosphere.multiscatter",
                                             "atmosphere.sky_view", "atmosphere.aerial_perspective", "geometry", "sky",
                                             "test after-opaque", "tonemap", "test after-tonemap"}))
      << graph;

  // The picture: the red-only tint removed green and blue from the sky; the overlay is pure green.
  Png img = load_png(dir / "shot.png");
  ASSERT_EQ(img.w, 160);
  const uint8_t* corner = img.px(4, 4);
  EXPECT_EQ(corner[0], 0);
  EXPECT_EQ(corner[1], 255);
  EXPECT_EQ(corner[2], 0);
  const uint8_t* sky = img.px(100, 10);
  EXPECT_GT(sky[0], 20);
  EXPECT_EQ(sky[1], 0);
  EXPECT_EQ(sky[2], 0);
  fs::remove_all(dir);
}

TEST(Module, BadModuleFlagIsRefusedNamingIt) {
  auto module = std::make_shared<TestModule>();
  std::vector<std::string> args{"run", "x.json", "--test-tint", "red"};
  auto argv = argv_of(args);
  try {
    app::parse_run_options(int(argv.size()), argv.data(), {module});
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--test-tint"), std::string::npos) << e.what();
  }
}

TEST(Module, UnknownComponentNamesEntityComponentAndKnownList) {
  app::SimulationDesc d;
  d.level = "tests/engine/app/data/unknown_component_level.json";
  d.modules = {std::make_shared<TestModule>()};
  try {
    app::Simulation sim(d);
    FAIL() << "accepted";
  } catch (const Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("unknown_component_level.json"), std::string::npos) << m;
    EXPECT_NE(m.find("$.entities[1]"), std::string::npos) << m;   // the entity
    EXPECT_NE(m.find("Cloudscape"), std::string::npos) << m;      // the component asked for
    EXPECT_NE(m.find("Spin"), std::string::npos) << m;            // the module's component is known
    EXPECT_NE(m.find("Transform"), std::string::npos) << m;       // and the engine's
  }
}

// Module shaders come from the renderer's pipeline library: editing one hot-reloads it.
TEST(Module, ModuleShadersHotReload) {
  fs::path root = test::unique_temp_path("cumulo_module_shaders");
  fs::remove_all(root);
  fs::copy("shaders", root, fs::copy_options::recursive);
  gpu::ContextDesc cd;
  cd.validation = true;
  gpu::Context ctx(cd);
  TestModule module;
  {
    render::FrameRenderer renderer(ctx, root);
    renderer.add_feature(module);
    render::FrameSnapshot s;
    s.width = 64;
    s.height = 36;
    scene::TimeOfDay tod;
    tod.hours = 12.0f;
    s.sun = scene::sun_light(tod, scene::Sun{});
    s.lighting = render::sky_lighting(s.sun);
    s.camera = scene::make_camera_view(scene::Transform::look_at({0, 10, 0}, {0, 60, -100}), scene::Camera{}, 64.0f / 36.0f);
    s.extensions.set(TintFrame{glm::vec4(1, 0, 0, 1), 0.0});
    auto render_once = [&] { return test::render_offscreen(ctx, renderer, s); };
    auto before = render_once();
    EXPECT_EQ(before.at(40, 4)[2], 0);  // red tint: no blue in the sky
    // Edit the module's shader: the fill now writes blue whatever the push constant says.
    fs::path fill = root / "test/module_fill.comp";
    std::string src = read_file_text(fill);
    size_t pos = src.find("imageStore(tint, ivec2(0), pc.color);");
    ASSERT_NE(pos, std::string::npos);
    src.replace(pos, std::string("imageStore(tint, ivec2(0), pc.color);").size(),
                "imageStore(tint, ivec2(0), vec4(0.0, 0.0, 1.0, 1.0));");
    fs::last_write_time(fill, fs::last_write_time(fill) - std::chrono::seconds(5));  // a different mtime for sure
    write_file_atomic(fill, src);
    EXPECT_TRUE(renderer.reload_shaders());
    EXPECT_TRUE(renderer.shader_errors().empty()) << renderer.shader_errors();
    auto after = render_once();
    EXPECT_EQ(after.at(40, 4)[0], 0);  // blue tint now: no red
    EXPECT_GT(after.at(40, 4)[2], 20);
    EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  }
  EXPECT_EQ(module.gpu_destroyed_, 1);
  fs::remove_all(root);
}
