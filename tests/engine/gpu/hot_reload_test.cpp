#include <gtest/gtest.h>

#include <fstream>

#include "engine/core/error.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline_library.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;
using cumulo::gpu::test::GpuTest;
namespace fs = std::filesystem;

namespace {

// Writes `text` and moves the mtime forward by `tick` seconds, so changes are seen even on file
// systems with coarse timestamps.
void write_source(const fs::path& p, const std::string& text, int tick) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::trunc) << text;
  fs::last_write_time(p, fs::file_time_type::clock::now() + std::chrono::seconds(tick));
}

std::string shader_with(const std::string& expr) {
  return "#version 460\n"
         "#extension GL_GOOGLE_include_directive : require\n"
         "#include \"lib/value.glsl\"\n"
         "layout(local_size_x = 1) in;\n"
         "layout(std430, set = 0, binding = 0) buffer Out { float v; };\n"
         "void main() {\n"
         "  v = " +
         expr +
         ";\n"
         "}\n";
}

float run(Context& ctx, Pipeline& p, Buffer& out) {
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    p.bind(cmd);
    DescriptorWriter().storage_buffer(0, out.handle()).push(ctx, cmd, p);
    vkCmdDispatch(cmd, 1, 1, 1);
  });
  float v = 0;
  out.download(&v, 4);
  return v;
}

}  // namespace

TEST_F(GpuTest, HotReloadKeepsOldPipelineOnErrorAndSwapsWhenFixed) {
  fs::path root = cache_ / "src";
  write_source(root / "lib" / "value.glsl", "float base_value() { return 1.0; }\n", 1);
  write_source(root / "reload.comp", shader_with("base_value()"), 1);
  PipelineLibrary lib(ctx(), root);
  Pipeline& p = lib.compute({.shader = "reload.comp", .name = "reload"});
  EXPECT_EQ(&lib.compute({.shader = "reload.comp", .name = "reload"}), &p);  // same description, same pipeline
  Buffer out(ctx(), {.size = 16, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "out"});
  EXPECT_EQ(run(ctx(), p, out), 1.0f);
  EXPECT_EQ(lib.poll_reload(), 0);  // nothing changed

  // Break the shader: the old pipeline keeps running and the error names file and line.
  VkPipeline before = p.handle();
  write_source(root / "reload.comp", shader_with("base_value() +"), 2);
  EXPECT_EQ(lib.poll_reload(), 0);
  EXPECT_EQ(p.handle(), before);
  std::string err = lib.last_error();
  EXPECT_NE(err.find("src/reload.comp:7: "), std::string::npos) << err;
  EXPECT_EQ(lib.reload_failures(), 1u);
  EXPECT_EQ(run(ctx(), p, out), 1.0f);
  EXPECT_EQ(lib.poll_reload(), 0);  // not retried until the file changes again
  EXPECT_EQ(lib.reload_failures(), 1u);

  // Fix it: a new pipeline, the error is gone.
  write_source(root / "reload.comp", shader_with("base_value() * 2.0"), 3);
  EXPECT_EQ(lib.poll_reload(), 1);
  EXPECT_TRUE(lib.last_error().empty()) << lib.last_error();
  EXPECT_EQ(run(ctx(), p, out), 2.0f);

  // Editing only the included file also triggers a rebuild.
  write_source(root / "lib" / "value.glsl", "float base_value() { return 5.0; }\n", 4);
  EXPECT_EQ(lib.poll_reload(), 1);
  EXPECT_EQ(run(ctx(), p, out), 10.0f);
  EXPECT_EQ(lib.reload_count(), 2u);
}

TEST_F(GpuTest, LibraryFirstBuildFailureThrows) {
  fs::path root = cache_ / "src";
  write_source(root / "bad.comp", "#version 460\nlayout(local_size_x = 1) in;\nvoid main() { nope(); }\n", 1);
  PipelineLibrary lib(ctx(), root);
  try {
    lib.compute({.shader = "bad.comp"});
    FAIL();
  } catch (const cumulo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("src/bad.comp:3: "), std::string::npos) << e.what();
  }
  EXPECT_EQ(lib.size(), 0u);
}
