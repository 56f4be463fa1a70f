// CompiledGraph::to_text() and to_dot(): the frame as a person reads it.
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::render {
namespace {

std::string stage_names(VkPipelineStageFlags2 s) {
  static const std::pair<VkPipelineStageFlags2, const char*> kNames[] = {
      {VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, "TOP"},
      {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, "DRAW_INDIRECT"},
      {VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, "VERTEX_INPUT"},
      {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, "VERTEX_SHADER"},
      {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, "FRAGMENT_SHADER"},
      {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, "EARLY_FRAGMENT_TESTS"},
      {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, "LATE_FRAGMENT_TESTS"},
      {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, "COLOR_ATTACHMENT_OUTPUT"},
      {VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, "COMPUTE_SHADER"},
      {VK_PIPELINE_STAGE_2_TRANSFER_BIT, "TRANSFER"},
      {VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, "BOTTOM"},
      {VK_PIPELINE_STAGE_2_HOST_BIT, "HOST"},
      {VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, "ALL_GRAPHICS"},
      {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, "ALL_COMMANDS"},
      {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, "INDEX_INPUT"},
      {VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, "VERTEX_ATTRIBUTE_INPUT"},
  };
  std::string out;
  for (auto& [bit, name] : kNames)
    if (s & bit) out += (out.empty() ? "" : "|") + std::string(name), s &= ~bit;
  if (s) out += (out.empty() ? "" : "|") + strf("0x%llx", (unsigned long long)s);
  return out.empty() ? "NONE" : out;
}

std::string access_names(VkAccessFlags2 a) {
  static const std::pair<VkAccessFlags2, const char*> kNames[] = {
      {VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, "INDIRECT_READ"},
      {VK_ACCESS_2_INDEX_READ_BIT, "INDEX_READ"},
      {VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT, "VERTEX_READ"},
      {VK_ACCESS_2_UNIFORM_READ_BIT, "UNIFORM_READ"},
      {VK_ACCESS_2_SHADER_READ_BIT, "SHADER_READ"},
      {VK_ACCESS_2_SHADER_WRITE_BIT, "SHADER_WRITE"},
      {VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, "COLOR_READ"},
      {VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, "COLOR_WRITE"},
      {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, "DEPTH_READ"},
      {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, "DEPTH_WRITE"},
      {VK_ACCESS_2_TRANSFER_READ_BIT, "TRANSFER_READ"},
      {VK_ACCESS_2_TRANSFER_WRITE_BIT, "TRANSFER_WRITE"},
      {VK_ACCESS_2_HOST_READ_BIT, "HOST_READ"},
      {VK_ACCESS_2_HOST_WRITE_BIT, "HOST_WRITE"},
      {VK_ACCESS_2_MEMORY_READ_BIT, "MEMORY_READ"},
      {VK_ACCESS_2_MEMORY_WRITE_BIT, "MEMORY_WRITE"},
      {VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, "SAMPLED_READ"},
      {VK_ACCESS_2_SHADER_STORAGE_READ_BIT, "STORAGE_READ"},
      {VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, "STORAGE_WRITE"},
  };
  std::string out;
  for (auto& [bit, name] : kNames)
    if (a & bit) out += (out.empty() ? "" : "|") + std::string(name), a &= ~bit;
  if (a) out += (out.empty() ? "" : "|") + strf("0x%llx", (unsigned long long)a);
  return out.empty() ? "NONE" : out;
}

const char* layout_name(VkImageLayout l) {
  switch (l) {
    case VK_IMAGE_LAYOUT_UNDEFINED:
      return "UNDEFINED";
    case VK_IMAGE_LAYOUT_GENERAL:
      return "GENERAL";
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
      return "COLOR_ATTACHMENT";
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL:
      return "DEPTH_STENCIL_ATTACHMENT";
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL:
      return "DEPTH_STENCIL_READ_ONLY";
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
      return "SHADER_READ_ONLY";
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
      return "TRANSFER_SRC";
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
      return "TRANSFER_DST";
    case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR:
      return "PRESENT_SRC";
    default:
      return "OTHER";
  }
}

void write_barrier(std::ostringstream& o, const Barrier& b) {
  o << "    barrier " << b.name << ": " << stage_names(b.src_stages) << " " << access_names(b.src_access) << " -> "
    << stage_names(b.dst_stages) << " " << access_names(b.dst_access);
  if (b.image) o << ", " << layout_name(b.old_layout) << " -> " << layout_name(b.new_layout);
  if (b.discard) o << " (discard)";
  o << "\n";
}

std::string dot_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::string CompiledGraph::to_text() const {
  std::ostringstream o;
  o << "render graph " << output_size.width << "x" << output_size.height << ", " << passes.size() << " passes, "
    << culled.size() << " culled, hash " << strf("%016llx", (unsigned long long)hash) << "\n";
  for (size_t i = 0; i < passes.size(); ++i) {
    const CompiledPass& p = passes[i];
    o << "pass " << i << " " << p.name << " (" << (p.queue == Queue::Compute ? "compute" : "graphics") << ")\n";
    for (const Barrier& b : p.barriers) write_barrier(o, b);
    for (const ResourceAccess& a : p.accesses)
      o << "    " << (a.write ? (a.read ? "read_write " : "write ") : "read ") << resources[a.resource].name << " as "
        << usage_name(a.usage) << "\n";
  }
  if (!final_barriers.empty()) o << "after the last pass\n";
  for (const Barrier& b : final_barriers) write_barrier(o, b);
  for (const std::string& c : culled) o << "culled " << c << "\n";
  o << "resources\n";
  for (const CompiledResource& r : resources) {
    o << "  " << r.name << (r.image ? " image " : " buffer ") << (r.imported ? "imported" : "transient");
    if (r.image)
      o << " " << r.extent.width << "x" << r.extent.height << "x" << r.extent.depth << " mips " << r.mips;
    else
      o << " " << r.size << " bytes";
    if (r.first_pass < 0)
      o << " unused";
    else
      o << " passes " << r.first_pass << ".." << r.last_pass;
    if (r.memory_block >= 0) o << " memory block " << r.memory_block;
    o << "\n";
  }
  for (size_t i = 0; i < memory_blocks.size(); ++i) {
    o << "memory block " << i << ": " << memory_blocks[i].size << " bytes, shared by";
    for (uint32_t r : memory_blocks[i].resources) o << " " << resources[r].name;
    o << "\n";
  }
  return o.str();
}

// Passes are boxes, resources ellipses (dashed when culled passes were their only users); an edge
// pass -> resource is a write, resource -> pass a read. Aliased resources share a fill colour.
std::string CompiledGraph::to_dot() const {
  static const char* kColors[] = {"lightblue", "palegreen", "lightsalmon", "khaki", "plum", "lightcyan", "wheat"};
  std::ostringstream o;
  o << "digraph render_graph {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
  for (size_t i = 0; i < passes.size(); ++i)
    o << "  p" << i << " [shape=box, style=filled, fillcolor=\""
      << (passes[i].queue == Queue::Compute ? "lightyellow" : "lightgrey") << "\", label=\"" << i << ": "
      << dot_escape(passes[i].name) << "\"];\n";
  for (size_t c = 0; c < culled.size(); ++c)
    o << "  c" << c << " [shape=box, style=dashed, label=\"" << dot_escape(culled[c]) << " (culled)\"];\n";
  for (size_t r = 0; r < resources.size(); ++r) {
    const CompiledResource& res = resources[r];
    if (res.first_pass < 0) continue;
    o << "  r" << r << " [shape=ellipse, label=\"" << dot_escape(res.name) << "\\n"
      << (res.image ? strf("%ux%ux%u", res.extent.width, res.extent.height, res.extent.depth)
                    : strf("%llu B", (unsigned long long)res.size))
      << (res.imported ? "\\nimported" : "") << "\"";
    if (res.memory_block >= 0) o << ", style=filled, fillcolor=\"" << kColors[res.memory_block % 7] << "\"";
    o << "];\n";
  }
  for (size_t i = 0; i < passes.size(); ++i)
    for (const ResourceAccess& a : passes[i].accesses) {
      if (a.read) o << "  r" << a.resource << " -> p" << i << " [label=\"" << usage_name(a.usage) << "\"];\n";
      if (a.write)
        o << "  p" << i << " -> r" << a.resource << " [label=\"" << usage_name(a.usage) << "\", color=red];\n";
    }
  o << "}\n";
  return o.str();
}

void CompiledGraph::write_dump(const std::string& path) const {
  const bool dot = path.size() > 4 && (path.ends_with(".dot") || path.ends_with(".gv"));
  try {
    write_file_atomic(path, dot ? to_dot() : to_text());
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // std::filesystem errors from creating the folder
    fail("%s: cannot write the render graph dump: %s", path.c_str(), e.what());
  }
}

}  // namespace cumulo::render
