#pragma once
// GLSL -> SPIR-V at run time (glslang library), with #include, defines and a disk cache.
//
//   gpu::ShaderCompiler compiler;                       // root = <repo>/shaders, cache =
//   gpu::default_cache_dir()/shaders gpu::CompiledShader cs = compiler.compile("engine/tonemap.frag", {{"USE_ACES",
//   "1"}}); cs.spirv;   // words cs.files;   // main file + every file it included (absolute), for hot reload
//
// - #include "x.glsl" (needs `#extension GL_GOOGLE_include_directive : require`) is resolved relative to
//   the including file first, then to the shaders root, like the build-time glslangValidator -I<root>.
// - Stage from the extension: .vert .frag .comp (or pass one).
// - Cache key: hash of (stage, defines, target, the source and every #include'd file's text); a hit
//   skips glslang entirely. Cache files are <cache_dir>/<16 hex>.spv, written atomically.
// - Errors throw cumulo::Error whose lines read "shaders/x/y.comp:LINE: message" (the file that holds
//   the error, include or main), so editors can jump to it.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cumulo::gpu {

enum class ShaderStage { Vertex, Fragment, Compute };

const char* stage_name(ShaderStage stage);
std::optional<ShaderStage> stage_from_path(const std::filesystem::path& path);

struct ShaderDefine {
  std::string name;
  std::string value = "1";
  bool operator==(const ShaderDefine&) const = default;
};

struct CompiledShader {
  std::vector<uint32_t> spirv;
  ShaderStage stage = ShaderStage::Compute;
  std::vector<std::filesystem::path> files;  // main file first, then includes (absolute paths)
  std::string display_name;                  // "shaders/engine/x.comp"
  uint64_t key = 0;                          // cache key
  bool from_cache = false;
};

class ShaderCompiler {
 public:
  // root: empty = <repo_root()>/shaders. cache_dir: not given = default_cache_dir()/shaders (the
  // Context's default folder); an empty path = no disk cache.
  explicit ShaderCompiler(std::filesystem::path root = {},
                          std::optional<std::filesystem::path> cache_dir = std::nullopt);

  // `path` relative to the root, or absolute. Throws cumulo::Error (file missing, compile error).
  CompiledShader compile(const std::filesystem::path& path, const std::vector<ShaderDefine>& defines = {},
                         std::optional<ShaderStage> stage = std::nullopt) const;

  const std::filesystem::path& root() const { return root_; }
  const std::filesystem::path& cache_dir() const { return cache_dir_; }
  std::filesystem::path resolve(const std::filesystem::path& path) const;  // -> absolute
  std::string display_name(const std::filesystem::path& absolute) const;   // "shaders/..." or the absolute path
  // Resolves an #include target the way glslang will: relative to `includer` dir, then the root.
  std::optional<std::filesystem::path> resolve_include(const std::string& name,
                                                       const std::filesystem::path& includer) const;

  // Statistics (for tests and logs).
  mutable uint32_t cache_hits = 0, compiles = 0;

 private:
  std::filesystem::path root_;
  std::filesystem::path cache_dir_;
};

}  // namespace cumulo::gpu
