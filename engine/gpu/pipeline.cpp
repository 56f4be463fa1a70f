#include "engine/gpu/pipeline.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/detail/spirv_reflect.h"
#include "engine/gpu/live_objects.h"
#include "engine/gpu/pipeline_cache.h"

namespace cumulo::gpu {

static VkShaderStageFlagBits vk_stage(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return VK_SHADER_STAGE_VERTEX_BIT;
    case ShaderStage::Fragment:
      return VK_SHADER_STAGE_FRAGMENT_BIT;
    case ShaderStage::Compute:
      return VK_SHADER_STAGE_COMPUTE_BIT;
  }
  return VK_SHADER_STAGE_COMPUTE_BIT;
}

namespace {
struct ShaderModule {
  VkDevice device;
  VkShaderModule module = VK_NULL_HANDLE;
  ShaderModule(VkDevice d, const CompiledShader& s) : device(d) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = s.spirv.size() * 4;
    info.pCode = s.spirv.data();
    VK_CHECK(vkCreateShaderModule(d, &info, nullptr, &module));
  }
  ~ShaderModule() { vkDestroyShaderModule(device, module, nullptr); }
};
}  // namespace

Pipeline& Pipeline::operator=(Pipeline&& o) noexcept {
  if (this != &o) {
    reset();
    ctx_ = o.ctx_;
    pipeline_ = o.pipeline_;
    layout_ = o.layout_;
    bind_point_ = o.bind_point_;
    set_layouts_ = std::move(o.set_layouts_);
    set0_push_ = o.set0_push_;
    push_size_ = o.push_size_;
    push_stages_ = o.push_stages_;
    bindings_ = std::move(o.bindings_);
    local_size_ = o.local_size_;
    files_ = std::move(o.files_);
    name_ = std::move(o.name_);
    o.pipeline_ = VK_NULL_HANDLE;
    o.layout_ = VK_NULL_HANDLE;
    o.set_layouts_.clear();
  }
  return *this;
}

void Pipeline::reset() {
  if (!ctx_) return;
  VkDevice d = ctx_->device();
  if (pipeline_) {
    vkDestroyPipeline(d, pipeline_, nullptr);
    detail::count_live(detail::LiveKind::Pipeline, -1);
  }
  if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
  for (auto l : set_layouts_)
    if (l) vkDestroyDescriptorSetLayout(d, l, nullptr);
  set_layouts_.clear();
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
}

VkDescriptorSetLayout Pipeline::set_layout(uint32_t set) const {
  return set < set_layouts_.size() ? set_layouts_[set] : VK_NULL_HANDLE;
}

const PipelineBinding* Pipeline::find_binding(uint32_t set, uint32_t binding) const {
  for (auto& b : bindings_)
    if (b.set == set && b.binding == binding) return &b;
  return nullptr;
}

void Pipeline::build_layout(Context& ctx, const std::vector<const CompiledShader*>& shaders) {
  ctx_ = &ctx;
  for (const CompiledShader* s : shaders) {
    detail::ShaderReflection r = detail::reflect_spirv(s->spirv, s->display_name);
    VkShaderStageFlags stage = vk_stage(s->stage);
    if (s->stage == ShaderStage::Compute) local_size_ = {r.local_size[0], r.local_size[1], r.local_size[2]};
    if (r.push_constant_size) {
      push_size_ = std::max(push_size_, (r.push_constant_size + 3u) & ~3u);
      push_stages_ |= stage;
    }
    for (auto& rb : r.bindings) {
      auto it = std::find_if(bindings_.begin(), bindings_.end(),
                             [&](auto& b) { return b.set == rb.set && b.binding == rb.binding; });
      if (it == bindings_.end()) {
        bindings_.push_back({rb.set, rb.binding, rb.type, rb.count, stage, rb.name});
      } else {
        if (it->type != rb.type || it->count != rb.count)
          fail("%s: set %u binding %u is declared differently in another stage of pipeline '%s'",
               s->display_name.c_str(), rb.set, rb.binding, name_.c_str());
        it->stages |= stage;
      }
    }
    for (auto& f : s->files)
      if (std::find(files_.begin(), files_.end(), f) == files_.end()) files_.push_back(f);
  }
  if (push_size_ > ctx.info().limits.maxPushConstantsSize)
    fail("pipeline '%s': %u bytes of push constants exceed the device limit %u", name_.c_str(), push_size_,
         ctx.info().limits.maxPushConstantsSize);
  uint32_t sets = 0;
  for (auto& b : bindings_) sets = std::max(sets, b.set + 1);
  set0_push_ = ctx.info().push_descriptors && sets > 0;
  if (set0_push_) {
    uint32_t n = 0;
    for (auto& b : bindings_)
      if (b.set == 0) n += b.count;
    if (n > ctx.info().max_push_descriptors)
      fail(
          "pipeline '%s': set 0 has %u descriptors, more than the %u a push-descriptor set may hold on %s; move some "
          "to set 1",
          name_.c_str(), n, ctx.info().max_push_descriptors, ctx.info().name.c_str());
  }
  set_layouts_.assign(sets, VK_NULL_HANDLE);
  for (uint32_t s = 0; s < sets; ++s) {
    std::vector<VkDescriptorSetLayoutBinding> lb;
    for (auto& b : bindings_)
      if (b.set == s) lb.push_back({b.binding, b.type, b.count, b.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    if (s == 0 && set0_push_) info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    info.bindingCount = uint32_t(lb.size());
    info.pBindings = lb.data();
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device(), &info, nullptr, &set_layouts_[s]));
  }
  VkPushConstantRange range{push_stages_, 0, push_size_};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = sets;
  info.pSetLayouts = set_layouts_.data();
  info.pushConstantRangeCount = push_size_ ? 1 : 0;
  info.pPushConstantRanges = &range;
  VK_CHECK(vkCreatePipelineLayout(ctx.device(), &info, nullptr, &layout_));
  if (!name_.empty()) ctx.set_name(layout_, name_);
}

Pipeline Pipeline::compute(Context& ctx, const CompiledShader& shader, const std::string& name) {
  if (shader.stage != ShaderStage::Compute) fail("%s: not a compute shader", shader.display_name.c_str());
  Pipeline p;
  p.name_ = name.empty() ? shader.display_name : name;
  p.bind_point_ = VK_PIPELINE_BIND_POINT_COMPUTE;
  p.build_layout(ctx, {&shader});
  ShaderModule mod(ctx.device(), shader);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = mod.module;
  info.stage.pName = "main";
  info.layout = p.layout_;
  VkResult r = vkCreateComputePipelines(ctx.device(), ctx.pipeline_cache().handle(), 1, &info, nullptr, &p.pipeline_);
  if (r != VK_SUCCESS) fail("%s: vkCreateComputePipelines failed: %s", shader.display_name.c_str(), vk_result_name(r));
  detail::count_live(detail::LiveKind::Pipeline, 1);
  ctx.set_name(p.pipeline_, p.name_);
  return p;
}

Pipeline Pipeline::compute(Context& ctx, const ShaderCompiler& compiler, const ComputePipelineDesc& desc) {
  return compute(ctx, compiler.compile(desc.shader, desc.defines, ShaderStage::Compute), desc.name);
}

static VkPipelineColorBlendAttachmentState blend_state(BlendMode m) {
  VkPipelineColorBlendAttachmentState s{};
  s.colorWriteMask =
      VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  if (m == BlendMode::None) return s;
  s.blendEnable = VK_TRUE;
  s.colorBlendOp = s.alphaBlendOp = VK_BLEND_OP_ADD;
  switch (m) {
    case BlendMode::Alpha:
      s.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
      s.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
      s.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      s.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
      break;
    case BlendMode::PremultipliedAlpha:
      s.srcColorBlendFactor = s.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      s.dstColorBlendFactor = s.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
      break;
    case BlendMode::Additive:
      s.srcColorBlendFactor = s.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      s.dstColorBlendFactor = s.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      break;
    default:
      break;
  }
  return s;
}

Pipeline Pipeline::graphics(Context& ctx, const CompiledShader& vs, const CompiledShader& fs,
                            const GraphicsPipelineDesc& desc) {
  if (vs.stage != ShaderStage::Vertex) fail("%s: not a vertex shader", vs.display_name.c_str());
  if (fs.stage != ShaderStage::Fragment) fail("%s: not a fragment shader", fs.display_name.c_str());
  Pipeline p;
  p.name_ = desc.name.empty() ? fs.display_name : desc.name;
  p.bind_point_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  p.build_layout(ctx, {&vs, &fs});
  ShaderModule vm(ctx.device(), vs), fm(ctx.device(), fs);
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vm.module;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fm.module;
  stages[1].pName = "main";

  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vi.vertexBindingDescriptionCount = uint32_t(desc.vertex_bindings.size());
  vi.pVertexBindingDescriptions = desc.vertex_bindings.data();
  vi.vertexAttributeDescriptionCount = uint32_t(desc.vertex_attributes.size());
  vi.pVertexAttributeDescriptions = desc.vertex_attributes.data();
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = desc.topology;
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = desc.polygon;
  rs.cullMode = desc.cull;
  rs.frontFace = desc.front_face;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = desc.depth_test;
  ds.depthWriteEnable = desc.depth_write;
  ds.depthCompareOp = desc.depth_compare;
  std::vector<VkPipelineColorBlendAttachmentState> blends;
  for (size_t i = 0; i < desc.color_formats.size(); ++i)
    blends.push_back(blend_state(i < desc.blend.size() ? desc.blend[i] : BlendMode::None));
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = uint32_t(blends.size());
  cb.pAttachments = blends.data();
  VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dy.dynamicStateCount = 2;
  dy.pDynamicStates = dyn;
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = uint32_t(desc.color_formats.size());
  rendering.pColorAttachmentFormats = desc.color_formats.data();
  rendering.depthAttachmentFormat = desc.depth_format;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.pNext = &rendering;
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vi;
  info.pInputAssemblyState = &ia;
  info.pViewportState = &vp;
  info.pRasterizationState = &rs;
  info.pMultisampleState = &ms;
  info.pDepthStencilState = &ds;
  info.pColorBlendState = &cb;
  info.pDynamicState = &dy;
  info.layout = p.layout_;
  VkResult r = vkCreateGraphicsPipelines(ctx.device(), ctx.pipeline_cache().handle(), 1, &info, nullptr, &p.pipeline_);
  if (r != VK_SUCCESS) fail("pipeline '%s': vkCreateGraphicsPipelines failed: %s", p.name_.c_str(), vk_result_name(r));
  detail::count_live(detail::LiveKind::Pipeline, 1);
  ctx.set_name(p.pipeline_, p.name_);
  return p;
}

Pipeline Pipeline::graphics(Context& ctx, const ShaderCompiler& compiler, const GraphicsPipelineDesc& desc) {
  CompiledShader vs = compiler.compile(desc.vertex, desc.defines, ShaderStage::Vertex);
  CompiledShader fs = compiler.compile(desc.fragment, desc.defines, ShaderStage::Fragment);
  return graphics(ctx, vs, fs, desc);
}

void Pipeline::push_constants(VkCommandBuffer cmd, const void* data, uint32_t size, uint32_t offset) const {
  if (offset + size > push_size_)
    fail("pipeline '%s': push of %u bytes at %u exceeds its %u-byte push-constant block", name_.c_str(), size, offset,
         push_size_);
  vkCmdPushConstants(cmd, layout_, push_stages_, offset, size, data);
}

void Pipeline::dispatch_threads(VkCommandBuffer cmd, uint32_t x, uint32_t y, uint32_t z) const {
  vkCmdDispatch(cmd, (x + local_size_[0] - 1) / local_size_[0], (y + local_size_[1] - 1) / local_size_[1],
                (z + local_size_[2] - 1) / local_size_[2]);
}

}  // namespace cumulo::gpu
