#pragma once
// A minimal glTF 2.0 binary (.glb) writer: one buffer (the BIN chunk), buffer views aligned to 4 bytes,
// accessors with min/max, and a JSON document the caller fills. Deterministic output (nlohmann's
// objects keep keys sorted; numbers are printed with round-trip precision).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace cumulo::scene {

class GlbWriter {
 public:
  GlbWriter();
  nlohmann::json& json() { return json_; }

  // Appends bytes to the BIN chunk as a bufferView; target 0 = none (images), 34962 = vertices, 34963 = indices.
  int add_view(std::span<const uint8_t> bytes, int target);
  int add_vec3(std::span<const glm::vec3> values, bool with_bounds);
  int add_vec2(std::span<const glm::vec2> values);
  int add_indices_u16(std::span<const uint16_t> values);
  int add_indices_u32(std::span<const uint32_t> values);
  int add_png_image(std::span<const uint8_t> png, const char* name);

  std::vector<uint8_t> finish() const;  // the whole .glb file
  // The same asset as a .gltf whose buffer is the external file `bin_uri` (write bin() there).
  std::string finish_gltf(const std::string& bin_uri) const;
  const std::vector<uint8_t>& bin() const { return bin_; }

 private:
  int add_accessor(int view, int component_type, size_t count, const char* type);
  nlohmann::json json_;
  std::vector<uint8_t> bin_;
};

}  // namespace cumulo::scene
