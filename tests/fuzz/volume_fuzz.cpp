// libFuzzer target: the .nvdf loader. Any input must either parse into a valid volume or throw
// cumulo::Error; a parsed volume must serialize and parse back to the same volume.
#include <cstdint>
#include <cstdlib>

#include <cstring>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "modules/clouds/volume/volume_file.h"

using namespace cumulo;
using namespace cumulo::clouds;

namespace {

// Small limits keep a lying header from allocating gigabytes inside the fuzzer.
const VolumeLoadLimits kLimits{.max_dimension = 256, .max_payload_bytes = 16u << 20};

// Mutated headers almost always fail the header checksum first; a copy with the checksums
// recomputed (header always, payload when stored raw) lets the fuzzer reach the later checks.
std::vector<uint8_t> with_fixed_checksums(const uint8_t* data, size_t size) {
  std::vector<uint8_t> b(data, data + size);
  if (size < 96) return b;
  uint32_t header_bytes, flags;
  std::memcpy(&header_bytes, &b[12], 4);
  std::memcpy(&flags, &b[16], 4);
  if (header_bytes < 104 || header_bytes > size) return b;
  if ((flags & 1u) == 0) {
    const uint64_t h = hash64(b.data() + header_bytes, size - header_bytes);
    std::memcpy(&b[88], &h, 8);
  }
  const uint64_t h = hash64(b.data(), header_bytes - 8);
  std::memcpy(&b[header_bytes - 8], &h, 8);
  return b;
}

void check(std::span<const uint8_t> bytes) {
  Volume v;
  try {
    v = parse_volume(bytes, "fuzz.nvdf", kLimits);
  } catch (const Error&) {
    return;
  }
  v.validate("fuzz roundtrip");
  for (bool compress : {false, true}) {
    const std::vector<uint8_t> again = serialize_volume(v, {.compress = compress});
    const Volume back = parse_volume(again, "fuzz roundtrip", kLimits);
    if (back.levels != v.levels || back.size != v.size || back.channels.size() != v.channels.size()) std::abort();
  }
  // Texel access over the whole first level must stay in bounds (ASan checks).
  if (v.encoding != VolumeEncoding::BC7) {
    const uint32_t comps = encoding_components(v.encoding);
    const glm::uvec3 s = v.level_size(v.mip_count() - 1);
    for (uint32_t z = 0; z < s.z; ++z)
      for (uint32_t y = 0; y < s.y; ++y)
        for (uint32_t x = 0; x < s.x; ++x)
          for (uint32_t c = 0; c < comps; ++c) (void)v.decoded(x, y, z, c, v.mip_count() - 1);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check(std::span<const uint8_t>(data, size));
  check(with_fixed_checksums(data, size));
  return 0;
}
