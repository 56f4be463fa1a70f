#pragma once
// Compute and graphics pipelines (graphics through dynamic rendering). Layouts are derived from the
// shaders (SPIR-V reflection): descriptor set layouts per set, one push-constant range.
// Convention: set 0 is a push-descriptor set when the device has VK_KHR_push_descriptor (lavapipe,
// all desktop drivers): fill it per dispatch/draw with gpu::DescriptorWriter::push. Sets 1+ are
// ordinary sets (allocate from a gpu::DescriptorPool with pipeline.set_layout(n)).
//
//   gpu::ShaderCompiler compiler({}, ctx.cache_dir() / "shaders");   // root <repo>/shaders
//   gpu::Pipeline blur = gpu::Pipeline::compute(ctx, compiler, {.shader = "engine/blur.comp",
//                                                               .defines = {{"RADIUS", "4"}}, .name = "blur"});
//   blur.bind(cmd);
//   gpu::DescriptorWriter().storage_image(0, out.view()).sampled_image(1, in.view(), sampler).push(ctx, cmd, blur);
//   blur.push_constants(cmd, params);
//   blur.dispatch_threads(cmd, 64, 64);             // group counts from the shader's local_size
//
//   gpu::GraphicsPipelineDesc g{.vertex = "engine/fullscreen.vert", .fragment = "engine/tonemap.frag",
//                               .color_formats = {VK_FORMAT_R8G8B8A8_UNORM}, .name = "tonemap"};
//   gpu::Pipeline tonemap = gpu::Pipeline::graphics(ctx, compiler, g);
//   // vkCmdBeginRendering(...); tonemap.bind(cmd); set viewport/scissor (dynamic state); vkCmdDraw(cmd, 3, 1, 0, 0);
//
// Every creation goes through ctx.pipeline_cache(). Errors (compile, missing file) throw cumulo::Error.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/gpu/shader_compiler.h"
#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

enum class BlendMode { None, Alpha, PremultipliedAlpha, Additive };

struct ComputePipelineDesc {
  std::filesystem::path shader;  // relative to the shaders root, or absolute
  std::vector<ShaderDefine> defines;
  std::string name;
};

struct GraphicsPipelineDesc {
  std::filesystem::path vertex, fragment;
  std::vector<ShaderDefine> defines;  // applied to both stages
  std::vector<VkFormat> color_formats;
  std::vector<BlendMode> blend;  // per color attachment; missing entries = None
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  bool depth_test = false, depth_write = false;
  VkCompareOp depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reverse-Z
  VkCullModeFlags cull = VK_CULL_MODE_NONE;
  VkFrontFace front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPolygonMode polygon = VK_POLYGON_MODE_FILL;
  std::vector<VkVertexInputBindingDescription> vertex_bindings;
  std::vector<VkVertexInputAttributeDescription> vertex_attributes;
  std::string name;
};

struct PipelineBinding {
  uint32_t set = 0, binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;
  VkShaderStageFlags stages = 0;
  std::string name;
};

class Pipeline {
 public:
  static Pipeline compute(Context& ctx, const ShaderCompiler& compiler, const ComputePipelineDesc& desc);
  static Pipeline graphics(Context& ctx, const ShaderCompiler& compiler, const GraphicsPipelineDesc& desc);
  // From already compiled SPIR-V (the library uses these).
  static Pipeline compute(Context& ctx, const CompiledShader& shader, const std::string& name);
  static Pipeline graphics(Context& ctx, const CompiledShader& vs, const CompiledShader& fs,
                           const GraphicsPipelineDesc& desc);

  Pipeline() = default;
  ~Pipeline() { reset(); }
  Pipeline(Pipeline&& o) noexcept { *this = std::move(o); }
  Pipeline& operator=(Pipeline&& o) noexcept;
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  void reset();
  explicit operator bool() const { return pipeline_ != VK_NULL_HANDLE; }

  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkPipelineBindPoint bind_point() const { return bind_point_; }
  VkDescriptorSetLayout set_layout(uint32_t set) const;  // VK_NULL_HANDLE beyond the used sets
  uint32_t set_count() const { return uint32_t(set_layouts_.size()); }
  bool set0_is_push() const { return set0_push_; }
  uint32_t push_constant_size() const { return push_size_; }
  VkShaderStageFlags push_constant_stages() const { return push_stages_; }
  const std::vector<PipelineBinding>& bindings() const { return bindings_; }
  const PipelineBinding* find_binding(uint32_t set, uint32_t binding) const;
  std::array<uint32_t, 3> local_size() const { return local_size_; }
  const std::vector<std::filesystem::path>& source_files() const { return files_; }
  const std::string& name() const { return name_; }

  void bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, bind_point_, pipeline_); }
  void push_constants(VkCommandBuffer cmd, const void* data, uint32_t size, uint32_t offset = 0) const;
  template <class T>
  void push_constants(VkCommandBuffer cmd, const T& value) const {
    push_constants(cmd, &value, uint32_t(sizeof(T)));
  }
  // vkCmdDispatch with ceil(threads / local_size) groups.
  void dispatch_threads(VkCommandBuffer cmd, uint32_t x, uint32_t y = 1, uint32_t z = 1) const;

 private:
  void build_layout(Context& ctx, const std::vector<const CompiledShader*>& shaders);

  Context* ctx_ = nullptr;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipelineBindPoint bind_point_ = VK_PIPELINE_BIND_POINT_COMPUTE;
  std::vector<VkDescriptorSetLayout> set_layouts_;
  bool set0_push_ = false;
  uint32_t push_size_ = 0;
  VkShaderStageFlags push_stages_ = 0;
  std::vector<PipelineBinding> bindings_;
  std::array<uint32_t, 3> local_size_{1, 1, 1};
  std::vector<std::filesystem::path> files_;
  std::string name_;
};

}  // namespace cumulo::gpu
