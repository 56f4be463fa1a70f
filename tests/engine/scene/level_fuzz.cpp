// libFuzzer target for the level loader (JSON text -> ECS entities through the component registry, models
// not opened): it may refuse an input with cumulo::Error; anything else (a crash, a sanitizer report,
// another exception, a half-loaded world) is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/core/error.h"
#include "engine/core/json.h"
#include "engine/core/log.h"
#include "engine/ecs/serialize.h"
#include "engine/ecs/world.h"
#include "engine/scene/level.h"
#include "engine/scene/serialization.h"

using namespace cumulo;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  log::set_level(log::Level::Error);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ecs::ComponentRegistry registry = [] {
    ecs::ComponentRegistry r;
    scene::register_components(r);
    return r;
  }();
  ecs::World world;
  try {
    JsonDocument doc = parse_json_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    scene::load_level_document(doc, "/nonexistent", world, registry, /*load_models=*/false);
  } catch (const Error&) {
    // Loading is all-or-nothing: a refused level leaves the world empty.
    if (world.alive_count() != 0) std::abort();
  }
  return 0;
}
