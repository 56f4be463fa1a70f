#include "engine/gpu/pipeline_library.h"

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

namespace fs = std::filesystem;

struct PipelineLibrary::Entry {
  bool is_compute = true;
  ComputePipelineDesc compute;
  GraphicsPipelineDesc graphics;
  std::string key;
  Pipeline pipeline;
  std::vector<std::pair<fs::path, fs::file_time_type>> stamps;  // sources as of the last build attempt
  std::string error;                                            // latest rebuild error, empty when current
};

std::vector<std::string> PipelineLibrary::keys() const {
  std::vector<std::string> k;
  for (const auto& e : entries_) k.push_back(e->key);
  return k;
}

static std::string defines_key(const std::vector<ShaderDefine>& d) {
  std::string k;
  for (auto& x : d) k += x.name + "=" + x.value + ";";
  return k;
}

static std::string graphics_key(const GraphicsPipelineDesc& g) {
  std::string k =
      "G|" + g.vertex.string() + "|" + g.fragment.string() + "|" + defines_key(g.defines) + "|" + g.name + "|";
  for (auto f : g.color_formats) k += std::to_string(int(f)) + ",";
  for (auto b : g.blend) k += "b" + std::to_string(int(b));
  k += strf("|%d%d%d%d%u%d%d%d|", int(g.depth_format), g.depth_test, g.depth_write, int(g.depth_compare), g.cull,
            int(g.front_face), int(g.topology), int(g.polygon));
  for (auto& b : g.vertex_bindings) k += strf("vb%u,%u,%d;", b.binding, b.stride, int(b.inputRate));
  for (auto& a : g.vertex_attributes) k += strf("va%u,%u,%d,%u;", a.location, a.binding, int(a.format), a.offset);
  return k;
}

PipelineLibrary::PipelineLibrary(Context& ctx, fs::path root, bool disk_cache)
    : ctx_(ctx), compiler_(std::move(root), disk_cache ? ctx.cache_dir() / "shaders" : fs::path()) {}

PipelineLibrary::~PipelineLibrary() = default;

void PipelineLibrary::stamp(Entry& e, const std::vector<fs::path>& files) {
  e.stamps.clear();
  for (auto& f : files) {
    std::error_code ec;
    auto t = fs::last_write_time(f, ec);
    e.stamps.emplace_back(f, ec ? fs::file_time_type::min() : t);
  }
}

bool PipelineLibrary::changed(const Entry& e) const {
  for (auto& [f, t] : e.stamps) {
    std::error_code ec;
    auto now = fs::last_write_time(f, ec);
    if (ec ? t != fs::file_time_type::min() : now != t) return true;
  }
  return false;
}

void PipelineLibrary::build(Entry& e) {
  if (e.is_compute) {
    e.pipeline = Pipeline::compute(ctx_, compiler_, e.compute);
  } else {
    e.pipeline = Pipeline::graphics(ctx_, compiler_, e.graphics);
  }
  stamp(e, e.pipeline.source_files());
}

Pipeline& PipelineLibrary::compute(const ComputePipelineDesc& desc) {
  std::string key = "C|" + desc.shader.string() + "|" + defines_key(desc.defines) + "|" + desc.name;
  for (auto& e : entries_)
    if (e->key == key) return e->pipeline;
  auto e = std::make_unique<Entry>();
  e->is_compute = true;
  e->compute = desc;
  e->key = key;
  build(*e);
  entries_.push_back(std::move(e));
  return entries_.back()->pipeline;
}

Pipeline& PipelineLibrary::graphics(const GraphicsPipelineDesc& desc) {
  std::string key = graphics_key(desc);
  for (auto& e : entries_)
    if (e->key == key) return e->pipeline;
  auto e = std::make_unique<Entry>();
  e->is_compute = false;
  e->graphics = desc;
  e->key = key;
  build(*e);
  entries_.push_back(std::move(e));
  return entries_.back()->pipeline;
}

int PipelineLibrary::poll_reload() {
  int rebuilt = 0;
  bool idle = false;
  for (auto& e : entries_) {
    if (!changed(*e)) continue;
    // Remember what we looked at, so a broken file is retried only after its next change.
    auto files = e->pipeline.source_files();
    stamp(*e, files);
    try {
      Pipeline fresh = e->is_compute ? Pipeline::compute(ctx_, compiler_, e->compute)
                                     : Pipeline::graphics(ctx_, compiler_, e->graphics);
      if (!idle) {
        ctx_.wait_idle();  // frames in flight may still use the old pipeline
        idle = true;
      }
      e->pipeline = std::move(fresh);
      stamp(*e, e->pipeline.source_files());  // the include set may have changed
      e->error.clear();
      ++rebuilt;
      ++reloads_;
      LOG_INFO("gpu: reloaded pipeline '%s'", e->pipeline.name().c_str());
    } catch (const Error& err) {
      e->error = err.what();
      ++failures_;
      LOG_ERROR("gpu: reload of pipeline '%s' failed, keeping the old one:\n%s", e->pipeline.name().c_str(),
                err.what());
    }
  }
  return rebuilt;
}

std::string PipelineLibrary::last_error() const {
  std::string out;
  for (auto& e : entries_) {
    if (e->error.empty()) continue;
    if (!out.empty()) out += "\n";
    out += e->error;
  }
  return out;
}

}  // namespace cumulo::gpu
