#include "editor/ui/imgui_layer.h"

#include <imgui.h>
#include <imgui_internal.h>
#include <imgui_impl_glfw.h>

#include <GLFW/glfw3.h>

#include "editor/ui/imgui_vulkan_backend.h"
#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/platform/window.h"

namespace cumulo::editor {
namespace {

// The layer whose window's key presses are being queued (one UI per process).
ImGuiLayer* g_key_queue_owner = nullptr;

void queue_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
  if (g_key_queue_owner && action == GLFW_PRESS) g_key_queue_owner->on_key_press(key, mods);
  ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
}

void check_vk(VkResult r) {
  if (r != VK_SUCCESS) fail("editor: Dear ImGui's Vulkan backend failed (VkResult %d)", int(r));
}

}  // namespace

ImGuiLayer::ImGuiLayer(platform::Window& window, gpu::Context& ctx) : window_(window), ctx_(ctx) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the layout is the editor's, not a file left in the working folder
  // The GLFW backend sets the cursor shape (and the cursor mode) on every frame, a request to the X
  // server each time; end_frame sets it when the shape changes.
  io.ConfigFlags |= ImGuiConfigFlags_NoMouseCursorChange;
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 3.0f;
  ImGui_ImplGlfw_InitForVulkan(window.handle(), true);
  // Dear ImGui 1.86 keeps only whether a key is down when the frame starts: a press and release between
  // two slow frames (a CPU device's) would be lost, so shortcuts read this queue of presses instead.
  g_key_queue_owner = this;
  glfwSetKeyCallback(window.handle(), queue_key);

  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pi.maxSets = 16;
  pi.poolSizeCount = 1;
  pi.pPoolSizes = sizes;
  check_vk(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &pool_));
  ctx.set_name(VK_OBJECT_TYPE_DESCRIPTOR_POOL, uint64_t(pool_), "editor.imgui.descriptors");

  init_pass_ = make_render_pass(VK_FORMAT_B8G8R8A8_UNORM);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = ctx.instance();
  info.PhysicalDevice = ctx.physical_device();
  info.Device = ctx.device();
  info.QueueFamily = ctx.queue_family();
  info.Queue = ctx.queue();
  info.DescriptorPool = pool_;
  info.MinImageCount = 2;
  // The backend cycles its vertex buffers over ImageCount draws and resizes one in place: more than the
  // frames in flight (plus a screenshot's extra draw) so a buffer is never replaced while the GPU reads it.
  info.ImageCount = gpu::kFramesInFlight + 2;
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = check_vk;
  ImGui_ImplVulkan_Init(&info, init_pass_);
  ctx.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

ImGuiLayer::~ImGuiLayer() {
  ctx_.wait_idle();
  for (auto& [frame, fb] : framebuffers_) vkDestroyFramebuffer(ctx_.device(), fb, nullptr);
  for (auto& [format, t] : targets_) {
    vkDestroyPipeline(ctx_.device(), t.pipeline, nullptr);
    vkDestroyRenderPass(ctx_.device(), t.render_pass, nullptr);
  }
  if (frame_open_) {  // closed by an exception between NewFrame and Render: end its windows first
    ImGui::ErrorCheckEndFrameRecover(nullptr);
    ImGui::EndFrame();
  }
  ImGui_ImplVulkan_Shutdown();
  glfwSetKeyCallback(window_.handle(), ImGui_ImplGlfw_KeyCallback);
  g_key_queue_owner = nullptr;
  ImGui_ImplGlfw_Shutdown();
  glfwSetCursor(window_.handle(), nullptr);
  for (auto& [shape, c] : cursors_)
    if (c) glfwDestroyCursor(c);
  ImGui::DestroyContext();
  vkDestroyRenderPass(ctx_.device(), init_pass_, nullptr);
  vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
}

void ImGuiLayer::begin_frame() {
  if (frame_open_) {
    ImGui::ErrorCheckEndFrameRecover(nullptr);
    ImGui::EndFrame();
  }
  ImGuiIO& io = ImGui::GetIO();
  // While the fly camera holds the cursor, the mouse is the camera's.
  if (glfwGetInputMode(window_.handle(), GLFW_CURSOR) == GLFW_CURSOR_DISABLED) io.ConfigFlags |= ImGuiConfigFlags_NoMouse;
  else io.ConfigFlags &= ~ImGuiConfigFlags_NoMouse;
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  frame_open_ = true;
}

void ImGuiLayer::end_frame() {
  const ImGuiMouseCursor cursor = ImGui::GetMouseCursor();
  if (cursor != cursor_ && glfwGetInputMode(window_.handle(), GLFW_CURSOR) != GLFW_CURSOR_DISABLED) {
    const int shape = cursor == ImGuiMouseCursor_TextInput                                       ? GLFW_IBEAM_CURSOR
                      : cursor == ImGuiMouseCursor_Hand                                          ? GLFW_HAND_CURSOR
                      : cursor == ImGuiMouseCursor_ResizeEW                                      ? GLFW_HRESIZE_CURSOR
                      : cursor == ImGuiMouseCursor_ResizeNS                                      ? GLFW_VRESIZE_CURSOR
                                                                                                 : GLFW_ARROW_CURSOR;
    auto it = cursors_.find(shape);
    if (it == cursors_.end()) it = cursors_.emplace(shape, glfwCreateStandardCursor(shape)).first;
    glfwSetCursor(window_.handle(), it->second);
    cursor_ = cursor;
  }
  ImGui::Render();
  frame_open_ = false;
  drawn_ = true;
}

std::vector<KeyPress> ImGuiLayer::take_key_presses() {
  std::vector<KeyPress> out;
  out.swap(key_presses_);
  return out;
}

bool ImGuiLayer::wants_keyboard() const { return ImGui::GetIO().WantCaptureKeyboard || ImGui::GetIO().WantTextInput; }
bool ImGuiLayer::wants_mouse() const { return ImGui::GetIO().WantCaptureMouse; }

VkRenderPass ImGuiLayer::make_render_pass(VkFormat format) const {
  // The graph has put the target in COLOR_ATTACHMENT_OPTIMAL and placed the barrier before the pass; the
  // UI draws over what tonemap wrote (load), and the graph takes the image on from the same layout.
  VkAttachmentDescription a{};
  a.format = format;
  a.samples = VK_SAMPLE_COUNT_1_BIT;
  a.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  a.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &ref;
  VkSubpassDependency deps[2]{};
  for (VkSubpassDependency& d : deps) {
    d.srcStageMask = d.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    d.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    d.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  }
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[1].srcSubpass = 0;
  deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  VkRenderPassCreateInfo ci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  ci.attachmentCount = 1;
  ci.pAttachments = &a;
  ci.subpassCount = 1;
  ci.pSubpasses = &sub;
  ci.dependencyCount = 2;
  ci.pDependencies = deps;
  VkRenderPass pass = VK_NULL_HANDLE;
  check_vk(vkCreateRenderPass(ctx_.device(), &ci, nullptr, &pass));
  ctx_.set_name(VK_OBJECT_TYPE_RENDER_PASS, uint64_t(pass), "editor.ui");
  return pass;
}

const ImGuiLayer::Target& ImGuiLayer::target_for(VkFormat format) {
  auto it = targets_.find(format);
  if (it != targets_.end()) return it->second;
  Target t;
  t.render_pass = make_render_pass(format);
  t.pipeline = imgui_vulkan_pipeline_for(t.render_pass);
  ctx_.set_name(VK_OBJECT_TYPE_PIPELINE, uint64_t(t.pipeline), "editor.ui");
  return targets_.emplace(format, t).first->second;
}

VkFramebuffer ImGuiLayer::make_framebuffer(VkRenderPass pass, VkImageView view, VkExtent2D extent) {
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = pass;
  fi.attachmentCount = 1;
  fi.pAttachments = &view;
  fi.width = extent.width;
  fi.height = extent.height;
  fi.layers = 1;
  VkFramebuffer fb = VK_NULL_HANDLE;
  check_vk(vkCreateFramebuffer(ctx_.device(), &fi, nullptr, &fb));
  framebuffers_.emplace_back(frame_, fb);
  return fb;
}

void ImGuiLayer::add_pass(render::StageContext& f) {
  if (!drawn_ || !f.output.valid()) return;
  ++frame_;
  // Framebuffers of frames that have completed (the ring waits for a slot's fence before reusing it).
  while (!framebuffers_.empty() && framebuffers_.front().first + gpu::kFramesInFlight + 2 <= frame_) {
    vkDestroyFramebuffer(ctx_.device(), framebuffers_.front().second, nullptr);
    framebuffers_.erase(framebuffers_.begin());
  }
  const Target& t = target_for(f.output_format);
  f.graph.add_pass(
      "editor.ui", render::Queue::Graphics,
      [&](render::PassBuilder& b) { f.output = b.read_write(f.output, render::Usage::ColorAttachment); },
      [this, t, out = f.output](render::PassContext& c) {
        ImDrawData* data = ImGui::GetDrawData();
        if (!data) return;
        const VkExtent3D e = c.extent(out);
        VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        bi.renderPass = t.render_pass;
        bi.framebuffer = make_framebuffer(t.render_pass, c.view(out), {e.width, e.height});
        bi.renderArea = {{0, 0}, {e.width, e.height}};
        vkCmdBeginRenderPass(c.cmd(), &bi, VK_SUBPASS_CONTENTS_INLINE);
        ImGui_ImplVulkan_RenderDrawData(data, c.cmd(), t.pipeline);
        vkCmdEndRenderPass(c.cmd());
      });
}

}  // namespace cumulo::editor
