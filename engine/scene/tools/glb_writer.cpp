#include "engine/scene/tools/glb_writer.h"

#include <cstring>
#include <string>

#include "engine/core/error.h"

namespace cumulo::scene {

namespace {
constexpr int kFloat = 5126, kU16 = 5123, kU32 = 5125;

void append_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));  // glb is little-endian
}
}  // namespace

GlbWriter::GlbWriter() {
  json_["asset"] = {{"version", "2.0"}, {"generator", "cumulo gen-terrain"}};
  json_["bufferViews"] = nlohmann::json::array();
  json_["accessors"] = nlohmann::json::array();
}

int GlbWriter::add_view(std::span<const uint8_t> bytes, int target) {
  while (bin_.size() % 4) bin_.push_back(0);
  nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}};
  if (target) v["target"] = target;
  bin_.insert(bin_.end(), bytes.begin(), bytes.end());
  json_["bufferViews"].push_back(v);
  return int(json_["bufferViews"].size()) - 1;
}

int GlbWriter::add_accessor(int view, int component_type, size_t count, const char* type) {
  json_["accessors"].push_back({{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
  return int(json_["accessors"].size()) - 1;
}

int GlbWriter::add_vec3(std::span<const glm::vec3> values, bool with_bounds) {
  int view = add_view({reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()}, 34962);
  int acc = add_accessor(view, kFloat, values.size(), "VEC3");
  if (with_bounds && !values.empty()) {  // required for POSITION (glTF 2.0 spec 3.6.2.4)
    glm::vec3 lo = values[0], hi = values[0];
    for (auto& v : values) lo = glm::min(lo, v), hi = glm::max(hi, v);
    json_["accessors"][size_t(acc)]["min"] = {lo.x, lo.y, lo.z};
    json_["accessors"][size_t(acc)]["max"] = {hi.x, hi.y, hi.z};
  }
  return acc;
}

int GlbWriter::add_vec2(std::span<const glm::vec2> values) {
  int view = add_view({reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()}, 34962);
  return add_accessor(view, kFloat, values.size(), "VEC2");
}

int GlbWriter::add_indices_u16(std::span<const uint16_t> values) {
  int view = add_view({reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()}, 34963);
  return add_accessor(view, kU16, values.size(), "SCALAR");
}

int GlbWriter::add_indices_u32(std::span<const uint32_t> values) {
  int view = add_view({reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()}, 34963);
  return add_accessor(view, kU32, values.size(), "SCALAR");
}

int GlbWriter::add_png_image(std::span<const uint8_t> png, const char* name) {
  int view = add_view(png, 0);
  if (!json_.contains("images")) json_["images"] = nlohmann::json::array();
  json_["images"].push_back({{"bufferView", view}, {"mimeType", "image/png"}, {"name", name}});
  return int(json_["images"].size()) - 1;
}

std::vector<uint8_t> GlbWriter::finish() const {
  nlohmann::json doc = json_;
  doc["buffers"] = nlohmann::json::array({{{"byteLength", bin_.size()}}});
  std::string text = doc.dump();
  while (text.size() % 4) text.push_back(' ');  // JSON chunk padding is spaces (glTF 2.0 spec 4.4.3.1)
  std::vector<uint8_t> bin = bin_;
  while (bin.size() % 4) bin.push_back(0);

  std::vector<uint8_t> out;
  out.reserve(12 + 8 + text.size() + 8 + bin.size());
  append_u32(out, 0x46546C67u);  // "glTF"
  append_u32(out, 2);
  append_u32(out, uint32_t(12 + 8 + text.size() + 8 + bin.size()));
  append_u32(out, uint32_t(text.size()));
  append_u32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  append_u32(out, uint32_t(bin.size()));
  append_u32(out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

std::string GlbWriter::finish_gltf(const std::string& bin_uri) const {
  nlohmann::json doc = json_;
  doc["buffers"] = nlohmann::json::array({{{"byteLength", bin_.size()}, {"uri", bin_uri}}});
  return doc.dump(2);
}

}  // namespace cumulo::scene
