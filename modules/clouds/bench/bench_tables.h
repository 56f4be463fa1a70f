#pragma once
// `cumulo bench`'s outputs: the markdown tables on stdout and the JSON of --out.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/gpu/context.h"
#include "modules/clouds/bench/bench_runs.h"

namespace cumulo::clouds::bench {

std::string runs_markdown(const std::vector<Run>& runs);
std::string summary_markdown(const std::vector<Summary>& sums);
nlohmann::ordered_json bench_json(const BenchOptions& o, const gpu::DeviceInfo& device, const nlohmann::ordered_json& memory,
                                  const std::vector<Run>& runs, const std::vector<Summary>& sums);

}  // namespace cumulo::clouds::bench
