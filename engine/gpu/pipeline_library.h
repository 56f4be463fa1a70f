#pragma once
// PipelineLibrary: owns pipelines built from shader files, remembers every source file (includes
// too) with its modification time, and rebuilds changed pipelines on poll_reload() (hot reload).
// A failed rebuild logs the compiler error, exposes it through last_error() (for on-screen display)
// and keeps the old pipeline running.
//
//   gpu::PipelineLibrary lib(ctx);                               // shaders root <repo>/shaders, disk cache on
//   gpu::Pipeline& march = lib.compute({.shader = "clouds/march.comp", .defines = {{"STEPS", "128"}}, .name =
//   "march"}); gpu::Pipeline& sky = lib.graphics({.vertex = "engine/fullscreen.vert", .fragment =
//   "engine/sky_atmosphere.frag",
//                                      .color_formats = {VK_FORMAT_R16G16B16A16_SFLOAT}, .name = "sky"});
//   // every frame (or every few frames) in windowed runs:
//   if (lib.poll_reload() > 0) LOG_INFO("shaders reloaded");
//   if (!lib.last_error().empty()) overlay_text(lib.last_error());  // "shaders/clouds/march.comp:42: ..."
//
// References returned by compute()/graphics() stay valid for the library's lifetime: a reload swaps
// the pipeline in place (after the device is idle, since frames in flight may still use the old one).
// The same description asked twice returns the same pipeline. The first build of a pipeline throws
// cumulo::Error on failure (there is no old pipeline to keep).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/gpu/pipeline.h"
#include "engine/gpu/shader_compiler.h"

namespace cumulo::gpu {

class Context;

class PipelineLibrary {
 public:
  // shader_root empty: <repo>/shaders. The SPIR-V disk cache goes to <ctx.cache_dir()>/shaders when enabled.
  explicit PipelineLibrary(Context& ctx, std::filesystem::path shader_root = {}, bool disk_cache = true);
  ~PipelineLibrary();
  PipelineLibrary(const PipelineLibrary&) = delete;
  PipelineLibrary& operator=(const PipelineLibrary&) = delete;

  Pipeline& compute(const ComputePipelineDesc& desc);
  Pipeline& graphics(const GraphicsPipelineDesc& desc);

  // Rebuilds every pipeline whose sources changed (mtime differs or a file vanished). Returns the
  // number rebuilt successfully. Never throws for shader errors.
  int poll_reload();
  // Errors of pipelines whose latest rebuild failed (one per line block); empty when all are current.
  std::string last_error() const;
  // Number of pipelines and how many reloads succeeded / failed so far.
  size_t size() const { return entries_.size(); }
  // Each pipeline's key (its shaders and defines), in creation order: what a run made (the soak's windows).
  std::vector<std::string> keys() const;
  uint32_t reload_count() const { return reloads_; }
  uint32_t reload_failures() const { return failures_; }
  ShaderCompiler& compiler() { return compiler_; }

 private:
  struct Entry;
  void build(Entry& e);
  void stamp(Entry& e, const std::vector<std::filesystem::path>& files);
  bool changed(const Entry& e) const;

  Context& ctx_;
  ShaderCompiler compiler_;
  std::vector<std::unique_ptr<Entry>> entries_;
  uint32_t reloads_ = 0, failures_ = 0;
};

}  // namespace cumulo::gpu
