#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/gpu/detail/spirv_reflect.h"
#include "engine/gpu/shader_compiler.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;
namespace fs = std::filesystem;

static void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

TEST(ShaderCompiler, CompilesWithIncludeAndDefineAndReflects) {
  ShaderCompiler c({}, fs::path());  // no disk cache: always compiles
  CompiledShader s = c.compile("test/fill_pattern.comp", {{"SCALE", "3.0"}});
  EXPECT_EQ(s.stage, ShaderStage::Compute);
  EXPECT_EQ(s.display_name, "shaders/test/fill_pattern.comp");
  ASSERT_GT(s.spirv.size(), 5u);
  EXPECT_EQ(s.spirv[0], 0x07230203u);
  ASSERT_EQ(s.files.size(), 2u);  // main + the include, for hot reload
  EXPECT_EQ(s.files[1].filename(), "test_common.glsl");
  auto r = detail::reflect_spirv(s.spirv, s.display_name);
  ASSERT_EQ(r.bindings.size(), 1u);
  EXPECT_EQ(r.bindings[0].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(r.bindings[0].name, "out_image");
  EXPECT_EQ(r.push_constant_size, 8u);
  EXPECT_EQ(r.local_size[0], 8u);
  EXPECT_EQ(r.local_size[1], 8u);
}

TEST(ShaderCompiler, ReflectsSamplersAndBuffers) {
  ShaderCompiler c({}, fs::path());  // no disk cache: always compiles
  CompiledShader s = c.compile("test/sample_volume.comp");
  auto r = detail::reflect_spirv(s.spirv, s.display_name);
  ASSERT_EQ(r.bindings.size(), 3u);
  EXPECT_EQ(r.bindings[0].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  EXPECT_EQ(r.bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  EXPECT_EQ(r.bindings[2].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  EXPECT_EQ(r.push_constant_size, 0u);
}

TEST(ShaderCompiler, ErrorNamesFileAndLine) {
  fs::path root = cumulo::test::fresh_temp_dir("cumulo_gpu_shader_error");
  write(root / "bad" / "broken.comp",
        "#version 460\nlayout(local_size_x = 1) in;\nvoid main() {\n  float x = undefined_thing;\n}\n");
  ShaderCompiler c(root, fs::path());
  try {
    c.compile("bad/broken.comp");
    FAIL() << "expected a compile error";
  } catch (const cumulo::Error& e) {
    std::string m = e.what();
    std::string want = root.filename().string() + "/bad/broken.comp:4: ";
    EXPECT_EQ(m.rfind(want, 0), 0u) << m;
    EXPECT_NE(m.find("undefined_thing"), std::string::npos) << m;
  }
  fs::remove_all(root);
}

TEST(ShaderCompiler, ErrorInsideIncludeNamesTheInclude) {
  fs::path root = cumulo::test::fresh_temp_dir("cumulo_gpu_shader_include_error");
  write(root / "lib" / "helpers.glsl", "float helper() {\n  return 1.0\n}\n");  // missing ';' on line 2
  write(root / "main.comp",
        "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"lib/helpers.glsl\"\n"
        "layout(local_size_x = 1) in;\nvoid main() { helper(); }\n");
  ShaderCompiler c(root, fs::path());
  try {
    c.compile("main.comp");
    FAIL();
  } catch (const cumulo::Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("lib/helpers.glsl:3: "), std::string::npos)
        << m;  // glslang reports at the '}' after the missing ';'
  }
  write(root / "missing.comp",
        "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"nope.glsl\"\nlayout(local_size_x = "
        "1) in;\nvoid main() {}\n");
  try {
    c.compile("missing.comp");
    FAIL();
  } catch (const cumulo::Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("missing.comp:3: "), std::string::npos) << m;
    EXPECT_NE(m.find("nope.glsl"), std::string::npos) << m;
  }
  EXPECT_THROW(c.compile("does_not_exist.comp"), cumulo::Error);
  fs::remove_all(root);
}

TEST(ShaderCompiler, DiskCacheKeyedBySourcesAndDefines) {
  fs::path root = cumulo::test::fresh_temp_dir("cumulo_gpu_shader_cache_src"),
           cache = cumulo::test::fresh_temp_dir("cumulo_gpu_shader_cache");
  write(root / "inc.glsl", "const float K = 1.0;\n");
  write(root / "a.comp",
        "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"inc.glsl\"\nlayout(local_size_x = "
        "1) in;\n"
        "layout(std430, binding = 0) buffer B { float v; };\nvoid main() { v = K * VALUE; }\n");
  ShaderCompiler c(root, cache);
  auto s1 = c.compile("a.comp", {{"VALUE", "2.0"}});
  EXPECT_FALSE(s1.from_cache);
  auto s2 = c.compile("a.comp", {{"VALUE", "2.0"}});
  EXPECT_TRUE(s2.from_cache);
  EXPECT_EQ(s1.spirv, s2.spirv);
  EXPECT_FALSE(c.compile("a.comp", {{"VALUE", "3.0"}}).from_cache);  // defines are part of the key
  write(root / "inc.glsl", "const float K = 2.0;\n");                // so is every included file
  auto s3 = c.compile("a.comp", {{"VALUE", "2.0"}});
  EXPECT_FALSE(s3.from_cache);
  EXPECT_NE(s3.key, s1.key);
  // A corrupt cache entry is ignored, not trusted.
  write(cache / cumulo::strf("%016llx.spv", (unsigned long long)s3.key), "garbage");
  EXPECT_FALSE(c.compile("a.comp", {{"VALUE", "2.0"}}).from_cache);
  fs::remove_all(root);
  fs::remove_all(cache);
}

TEST(ShaderCompiler, DefaultDiskCacheFollowsCumuloCacheDir) {
  cumulo::test::TempDir tmp("cumulo_gpu_default_cache");
  ::setenv("CUMULO_CACHE_DIR", tmp.path.c_str(), 1);
  ShaderCompiler c;
  ::unsetenv("CUMULO_CACHE_DIR");
  EXPECT_EQ(c.cache_dir(), tmp.path / "shaders");
  EXPECT_FALSE(c.compile("test/fill_pattern.comp").from_cache);
  EXPECT_TRUE(c.compile("test/fill_pattern.comp").from_cache);
}
