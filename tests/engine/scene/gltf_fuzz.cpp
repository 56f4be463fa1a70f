// libFuzzer target for the glTF loader (load_gltf_from_memory, external files refused): it may refuse an
// input with cumulo::Error; anything else (a crash, a sanitizer report, another exception, an index past
// its vertices, a texture of the wrong size) is a finding.
// Level JSON is fuzzed by level_fuzz.cpp.
#include <cstdint>
#include <cstdlib>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/scene/gltf.h"

using namespace cumulo;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  log::set_level(log::Level::Error);  // corrupted images and unknown fields warn on every input
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    scene::Model m = scene::load_gltf_from_memory({data, size}, "fuzz.glb", {});
    for (const scene::Mesh& mesh : m.meshes)
      for (uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size()) std::abort();
    for (const scene::Texture& t : m.textures)
      if (t.rgba.size() != size_t(t.width) * t.height * 4) std::abort();
  } catch (const Error&) {
  }
  return 0;
}
