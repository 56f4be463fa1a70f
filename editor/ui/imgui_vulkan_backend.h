#pragma once
// The Dear ImGui 1.86 Vulkan backend (compiled from Debian's libimgui-dev sources) plus one addition:
// a pipeline of the backend's for another render pass (another target format).
#include <vulkan/vulkan.h>

#include <imgui.h>
#include <imgui_impl_vulkan.h>

namespace cumulo::editor {

// After ImGui_ImplVulkan_Init: the backend's pipeline for `render_pass` (subpass 0). The caller destroys it.
VkPipeline imgui_vulkan_pipeline_for(VkRenderPass render_pass);

}  // namespace cumulo::editor
