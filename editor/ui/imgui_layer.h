#pragma once
// Dear ImGui in a windowed run: the context, the GLFW backend (its callbacks chained to the window's),
// the Vulkan backend, and the UI pass that draws the frame's widgets over the display-referred output
// at render::Stage::AfterTonemap (DESIGN.md: the editor's pass sits after tonemap).
//
//   ImGuiLayer ui(window, ctx);          // on_window_open
//   ui.begin_frame();  ...ImGui calls...  ui.end_frame();      // every frame, before extract
//   ui.add_pass(stage_context);          // Stage::AfterTonemap: "editor.ui" over f.output
//
// Debian's backend (1.86) needs a VkRenderPass (no dynamic rendering): one render pass and pipeline are
// made per output format (swapchain, offscreen screenshot); a framebuffer per frame, destroyed once no
// frame in flight can use it (a cache keyed by image view could outlive a recreated swapchain's views).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/render/render_feature.h"

struct GLFWcursor;

namespace cumulo::gpu {
class Context;
}
namespace cumulo::platform {
class Window;
}

namespace cumulo::editor {

// A key that went down since the last frame, with its modifiers (GLFW key and mod codes).
struct KeyPress {
  int key = 0, mods = 0;
};

class ImGuiLayer {
 public:
  ImGuiLayer(platform::Window& window, gpu::Context& ctx);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  void begin_frame();  // ends a frame that was never drawn (a skipped present) first
  void end_frame();    // ImGui::Render: the draw data the next add_pass draws
  // What ImGui took from the last frame's input (a text field, a drag over a panel).
  bool wants_keyboard() const;
  bool wants_mouse() const;
  // Key presses since the last call, in order (shortcuts: none is lost between two slow frames).
  std::vector<KeyPress> take_key_presses();
  void on_key_press(int key, int mods) { key_presses_.push_back({key, mods}); }
  // The UI pass over f.output (Stage::AfterTonemap).
  void add_pass(render::StageContext& f);

 private:
  struct Target {
    VkRenderPass render_pass = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
  };
  const Target& target_for(VkFormat format);
  VkFramebuffer make_framebuffer(VkRenderPass pass, VkImageView view, VkExtent2D extent);
  VkRenderPass make_render_pass(VkFormat format) const;

  platform::Window& window_;
  gpu::Context& ctx_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkRenderPass init_pass_ = VK_NULL_HANDLE;  // the backend's own pipeline's (B8G8R8A8_UNORM)
  std::map<VkFormat, Target> targets_;
  std::vector<std::pair<uint64_t, VkFramebuffer>> framebuffers_;  // (frame made, framebuffer)
  uint64_t frame_ = 0;
  std::vector<KeyPress> key_presses_;
  int cursor_ = -1;                     // the ImGuiMouseCursor last set
  std::map<int, GLFWcursor*> cursors_;  // by GLFW standard shape
  bool frame_open_ = false, drawn_ = false;
};

}  // namespace cumulo::editor
