#pragma once
// `cumulo reference` and `cumulo fidelity` (issue 11), and what they share: the tracer's command-line
// options and the loop that accumulates a reference image with progress and an ETA.
#include <cstdint>
#include <string>

#include "engine/ecs/entity.h"
#include "modules/clouds/options/clouds_run.h"
#include "modules/clouds/reference/reference_tracer.h"

namespace cumulo {
class ArgParser;
class CommandRegistry;
}  // namespace cumulo

namespace cumulo::clouds {

class RenderSession;

struct ReferenceOptions {
  uint32_t spp = 256;
  uint32_t max_bounces = 64;
  std::string phase_text = "cloud";
  render::ReferencePhase phase = render::ReferencePhase::Cloud;
  uint32_t seed = 1;
};
void add_reference_options(ArgParser& p, ReferenceOptions& o);
void check_reference_options(ReferenceOptions& o);  // throws naming the flag

// Renders frames from `camera` with the tracer set on the clouds feature until `o.spp` samples per pixel,
// printing progress (and an ETA) to stderr; `seconds`: the time it took.
render::ReferenceImage accumulate_reference(RenderSession& session, render::ReferenceTracer& tracer, ecs::Entity camera,
                                            const ReferenceOptions& o, const std::string& label, double* seconds);

void register_reference_command(CommandRegistry& registry, const CloudsRun& run);
void register_fidelity_command(CommandRegistry& registry, const CloudsRun& run);

}  // namespace cumulo::clouds
