// The cloudscapes' move handles in the viewport: a ring at each Cloudscape's origin; a left-button drag
// slides it over the horizontal plane at its height (the ray through the cursor meets that plane), and
// the release is one undoable world edit, like a drag of the panel's position fields.
#include <imgui.h>

#include <cmath>
#include <optional>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "engine/scene/components.h"
#include "modules/clouds/scene/cloudscape.h"

namespace cumulo::editor {
namespace {

struct HandleDrag {
  ecs::Entity entity;
  glm::vec3 start{0.0f};   // the position when the drag began
  glm::vec3 offset{0.0f};  // from the plane hit under the cursor to the position
};

// Where the ray through the cursor meets the plane y = height (none when parallel or behind).
std::optional<glm::vec3> cursor_on_plane(const Editor& e, float height) {
  const ImVec2 size = ImGui::GetMainViewport()->Size;
  const ImVec2 m = ImGui::GetIO().MousePos;
  const glm::vec2 ndc(m.x / size.x * 2.0f - 1.0f, m.y / size.y * 2.0f - 1.0f);
  const glm::vec3 dir = e.camera.ray_direction(ndc);
  if (std::abs(dir.y) < 1e-4f) return std::nullopt;
  const float t = (height - e.camera.position.y) / dir.y;
  if (t <= 0.0f || t > 100000.0f) return std::nullopt;
  return e.camera.position + dir * t;
}

}  // namespace

void draw_cloudscape_handles(Editor& e) {
  static std::optional<HandleDrag> drag;
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const ImGuiIO& io = ImGui::GetIO();
  ecs::World& w = e.world();
  const bool free_mouse = !io.WantCaptureMouse;
  w.view<const clouds::Cloudscape, scene::Transform>().each(
      [&](ecs::Entity ent, const clouds::Cloudscape&, scene::Transform& t) {
        ImVec2 s;
        if (!world_to_screen(e, t.position, s)) return;
        const bool dragging = drag && drag->entity == ent;
        const float dx = io.MousePos.x - s.x, dy = io.MousePos.y - s.y;
        const bool hovered = free_mouse && dx * dx + dy * dy < 144.0f;
        const ImU32 colour = dragging ? IM_COL32(255, 255, 120, 255) : hovered ? IM_COL32(255, 255, 255, 255)
                                                                              : IM_COL32(255, 255, 255, 150);
        dl->AddCircle(s, 9.0f, colour, 20, 2.0f);
        const auto* n = static_cast<const ecs::World&>(w).try_get<ecs::Name>(ent);
        dl->AddText(ImVec2(s.x + 12.0f, s.y - 7.0f), colour, n ? n->value.c_str() : "cloudscape");
        if (!drag && hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
          if (auto hit = cursor_on_plane(e, t.position.y)) drag = HandleDrag{ent, t.position, t.position - *hit};
        }
      });
  if (!drag) return;
  auto* t = w.try_get<scene::Transform>(drag->entity);
  if (!t) {
    drag.reset();
    return;
  }
  if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    if (auto hit = cursor_on_plane(e, drag->start.y)) t->position = *hit + drag->offset;
    return;
  }
  if (t->position != drag->start) {
    const ecs::Entity ent = drag->entity;
    auto put = [ent](glm::vec3 p) {
      return [ent, p](ecs::World& world) {
        if (auto* tr = world.try_get<scene::Transform>(ent)) tr->position = p;
      };
    };
    e.push_world_edit("move cloudscape", put(drag->start), put(t->position));
  }
  drag.reset();
}

}  // namespace cumulo::editor
