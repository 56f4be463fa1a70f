// libFuzzer target: the cloudscape recipe parser. Any text must either parse into a recipe whose
// edits evaluate to finite or "far" values, or throw cumulo::Error (never crash, hang or leak).
// File edits (mesh, volume) are refused: fuzz input must not name files to read.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/core/error.h"
#include "modules/clouds/bake/compose.h"
#include "modules/clouds/bake/recipe.h"

using namespace cumulo;
using namespace cumulo::clouds::bake;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  RecipeOptions opt;
  opt.allow_files = false;
  try {
    Recipe r = parse_recipe_text(text, "fuzz.json", "", opt);
    // Evaluate the parsed field at a few points of its box: must not crash or produce NaN.
    for (int i = 0; i < 8; ++i) {
      glm::vec3 t((i & 1) ? 0.25f : 0.75f, (i & 2) ? 0.3f : 0.6f, (i & 4) ? 0.2f : 0.8f);
      EvalSample s = evaluate_point(r, r.bounds_min + (r.bounds_max - r.bounds_min) * t);
      if (std::isnan(s.d) || std::isnan(s.detail_type) || std::isnan(s.density_scale)) std::abort();
    }
  } catch (const Error&) {
  }
  return 0;
}
