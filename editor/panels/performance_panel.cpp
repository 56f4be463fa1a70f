// Performance: the render graph's per-pass GPU times (timestamps of the last completed frame), the
// frame-time plot, the budget mode and its budget (dynamic resolution), and the compiled graph's passes
// with the resources each touches.
#include <imgui.h>

#include <algorithm>
#include <vector>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "engine/render/budget_mode.h"
#include "engine/render/dynamic_resolution.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::editor {

void draw_performance_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  app::WindowServices& ws = e.window();
  // Frame time.
  std::vector<float> ms(e.frame_ms.begin(), e.frame_ms.end());
  float worst = 0.0f, sum = 0.0f;
  for (float v : ms) worst = std::max(worst, v), sum += v;
  const float budget = float(ws.resolution.budget_ms(ws.mode));
  char overlay[96];
  std::snprintf(overlay, sizeof overlay, "frame %.1f ms avg, %.1f worst (budget %.1f); editor %.2f ms", ms.empty() ? 0.0f : sum / float(ms.size()),
                worst, budget, e.ui_cpu_ms);
  ImGui::PlotLines("##frames", ms.data(), int(ms.size()), 0, overlay, 0.0f, std::max(worst, budget) * 1.1f,
                   ImVec2(ImGui::GetContentRegionAvail().x, 40.0f));  // 1.86 takes no negative width here
  int mode = ws.mode == render::BudgetMode::Hz30 ? 0 : ws.mode == render::BudgetMode::Hz40 ? 1 : 2;
  ImGui::SetNextItemWidth(90.0f);
  if (ImGui::Combo("budget mode", &mode, "30 Hz\0" "40 Hz\0" "60 Hz\0"))
    ws.mode = mode == 0 ? render::BudgetMode::Hz30 : mode == 1 ? render::BudgetMode::Hz40 : render::BudgetMode::Hz60;
  item_tooltip("30 Hz: one full-resolution cloud march; 40/60 Hz: the 2023 talk's near/far split at 200 m.");
  // The budget: the mode's frame time times the device factor; dynamic resolution holds the frame inside it.
  ImGui::SameLine();
  float budget_scale = float(ws.resolution.budget_scale());
  ImGui::SetNextItemWidth(90.0f);
  if (ImGui::DragFloat("budget x", &budget_scale, 0.05f, 0.1f, 20.0f, "%.2f") && budget_scale > 0.0f)
    ws.resolution.set_budget_scale(budget_scale);
  item_tooltip("The budget mode's frame time times this (3 by default on a CPU device: 60 Hz plans for 50 ms).");
  ImGui::SameLine();
  bool dynamic = ws.resolution.enabled();
  if (ImGui::Checkbox("dynamic resolution", &dynamic)) ws.resolution.set_enabled(dynamic);
  item_tooltip("Scale the cloud march and the 2.5D sky so the frame's GPU time stays inside the budget.");
  ImGui::Text("budget %.1f ms; clouds and 2.5D sky at %.0f %% of the output (%u changes)", budget,
              100.0 * ws.resolution.scale(), ws.resolution.changes());

  if (ImGui::BeginTable("perf", 2, ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_ScrollY)) {
    ImGui::TableSetupScrollFreeze(0, 0);
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    // Per-pass GPU time, most expensive first.
    auto timings = ws.renderer.pass_timings();
    double total = 0.0;
    for (const auto& t : timings) total += t.second;
    std::sort(timings.begin(), timings.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    ImGui::Text("GPU %.2f ms in %zu passes", total, timings.size());
    for (const auto& [name, t] : timings) {
      ImGui::ProgressBar(total > 0.0 ? float(t / total) : 0.0f, ImVec2(60.0f, 0.0f), "");
      ImGui::SameLine();
      ImGui::Text("%6.2f %s", t, name.c_str());
    }
    ImGui::TableNextColumn();
    // The compiled graph: passes in execution order with what they read and write.
    if (!ws.renderer.has_recorded()) {
      ImGui::TextDisabled("render graph: no frame yet");
      ImGui::EndTable();
      return ImGui::End();
    }
    const render::CompiledGraph& g = ws.renderer.last_compiled();
    ImGui::Text("render graph: %zu passes, %zu culled, %zu resources", g.passes.size(), g.culled.size(), g.resources.size());
    for (const render::CompiledPass& p : g.passes) {
      if (!ImGui::TreeNode(p.name.c_str())) continue;
      for (const render::ResourceAccess& a : p.accesses) {
        if (a.resource >= g.resources.size()) continue;
        const render::CompiledResource& r = g.resources[a.resource];
        ImGui::BulletText("%s %s (%s%s)", a.write ? (a.read ? "rw" : "w ") : "r ", r.name.c_str(), render::usage_name(a.usage),
                          r.imported ? ", imported" : "");
      }
      ImGui::TreePop();
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace cumulo::editor
