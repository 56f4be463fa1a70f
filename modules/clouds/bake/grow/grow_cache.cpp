#include "modules/clouds/bake/grow/grow_cache.h"

#include <cstdio>
#include <optional>

#include "engine/core/error.h"
#include "engine/core/file_lock.h"
#include "engine/core/progress.h"
#include "modules/clouds/bake/grow/grown_cloud.h"

namespace cumulo::clouds::grow {

namespace fs = std::filesystem;

namespace {

bool complete(const fs::path& dir, const std::string& key) {
  std::error_code ec;
  return fs::is_regular_file(dir / "grown.nvdf", ec) && recorded_grow_key(dir) == key;
}

}  // namespace

fs::path committed_grow_folder(const fs::path& spec_path) { return spec_path.parent_path() / spec_path.stem(); }

fs::path cached_grow_folder(const GrowSpec& spec, const fs::path& spec_path) {
  return cache_dir() / "grown" / (spec_path.stem().string() + "-" + grow_key_hex(spec));
}

ResolvedGrown resolve_grown(const GrowSpec& spec, const fs::path& spec_path, bool show_progress) {
  const std::string key = grow_key_hex(spec);
  ResolvedGrown r;
  r.dir = committed_grow_folder(spec_path);
  if (complete(r.dir, key)) {
    r.committed = true;
    return r;
  }
  r.dir = cached_grow_folder(spec, spec_path);
  if (complete(r.dir, key)) return r;
  std::error_code ec;
  fs::create_directories(r.dir.parent_path(), ec);
  if (ec) fail("%s: cannot create the grow cache %s: %s", spec.file.c_str(), r.dir.parent_path().string().c_str(),
               ec.message().c_str());
  FileLock lock(r.dir.string() + ".lock");
  if (complete(r.dir, key)) return r;  // another process grew it while we waited
  std::printf("cumulo: growing %s into the grow cache %s (the spec or the solver changed since it was committed)\n",
              spec_path.string().c_str(), r.dir.string().c_str());
  std::fflush(stdout);
  GrowReport report;
  std::optional<Progress> progress;
  if (show_progress) progress.emplace("grow " + spec_path.filename().string(), double(spec.steps));
  GrownCloud g = grow_cloud(spec, &report, progress ? &*progress : nullptr);
  if (progress) progress->finish();
  const fs::path tmp = r.dir.string() + ".partial";
  fs::remove_all(tmp, ec);
  write_grow_outputs(spec, g, report, tmp);
  fs::remove_all(r.dir, ec);
  fs::rename(tmp, r.dir, ec);
  if (ec) fail("%s: cannot move the grown cloud into %s: %s", spec.file.c_str(), r.dir.string().c_str(), ec.message().c_str());
  r.grew = true;
  return r;
}

}  // namespace cumulo::clouds::grow
