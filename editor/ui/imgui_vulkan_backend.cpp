// Debian's Dear ImGui 1.86 ships its Vulkan backend as a source file, built into the editor here. That
// backend makes one pipeline for the render pass given at init; the editor draws into targets of more
// than one format (the swapchain, the offscreen screenshot), so this file also exposes the backend's own
// pipeline factory for further render passes (the same shaders, layout and font descriptor).
#include "/usr/share/doc/libimgui-dev/examples/backends/imgui_impl_vulkan.cpp"

#include "editor/ui/imgui_vulkan_backend.h"

namespace cumulo::editor {

VkPipeline imgui_vulkan_pipeline_for(VkRenderPass render_pass) {
  ImGui_ImplVulkan_Data* bd = ImGui_ImplVulkan_GetBackendData();
  IM_ASSERT(bd && "ImGui_ImplVulkan_Init first");
  ImGui_ImplVulkan_InitInfo* v = &bd->VulkanInitInfo;
  VkPipeline pipeline = VK_NULL_HANDLE;
  ImGui_ImplVulkan_CreatePipeline(v->Device, v->Allocator, v->PipelineCache, render_pass, v->MSAASamples, &pipeline,
                                  0);
  return pipeline;
}

}  // namespace cumulo::editor
