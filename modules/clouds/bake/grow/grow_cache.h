#pragma once
// Where a grow spec's cloud comes from, in order:
//  1. the committed folder beside the spec (`<spec folder>/<spec stem>/`, written by
//     `cumulo grow SPEC -o <that folder>`) when its grow_report.json records the spec's key;
//  2. the grow cache, `<cache>/grown/<stem>-<key>/` (CUMULO_CACHE_DIR, default ~/.cache/cumulo);
//  3. otherwise it is grown into the cache now (a progress line with an ETA), under a file lock so
//     two processes never grow the same spec at once, written beside and renamed when complete.
// The key hashes the spec's merged content and kSolverVersion, never file times: an unchanged spec
// in a fresh clone finds its committed cloud, and a changed spec or solver regrows.
#include <filesystem>
#include <string>

#include "modules/clouds/bake/grow/grow_spec.h"

namespace cumulo::clouds::grow {

struct ResolvedGrown {
  std::filesystem::path dir;  // holds grown.nvdf and grow_report.json
  bool committed = false;     // the folder beside the spec
  bool grew = false;          // grown by this call
};

std::filesystem::path committed_grow_folder(const std::filesystem::path& spec_path);
std::filesystem::path cached_grow_folder(const GrowSpec& spec, const std::filesystem::path& spec_path);

ResolvedGrown resolve_grown(const GrowSpec& spec, const std::filesystem::path& spec_path, bool show_progress = true);

}  // namespace cumulo::clouds::grow
