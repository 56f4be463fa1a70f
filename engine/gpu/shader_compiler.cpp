#include "engine/gpu/shader_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

namespace fs = std::filesystem;

const char* stage_name(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return "vertex";
    case ShaderStage::Fragment:
      return "fragment";
    case ShaderStage::Compute:
      return "compute";
  }
  return "?";
}

std::optional<ShaderStage> stage_from_path(const fs::path& p) {
  std::string ext = p.extension().string();
  if (ext == ".vert") return ShaderStage::Vertex;
  if (ext == ".frag") return ShaderStage::Fragment;
  if (ext == ".comp") return ShaderStage::Compute;
  return std::nullopt;
}

static EShLanguage to_glslang(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return EShLangVertex;
    case ShaderStage::Fragment:
      return EShLangFragment;
    case ShaderStage::Compute:
      return EShLangCompute;
  }
  return EShLangCompute;
}

static std::mutex g_glslang_mutex;  // glslang's global state (symbol tables, pools) is set up per process

static void init_glslang() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

ShaderCompiler::ShaderCompiler(fs::path root, std::optional<fs::path> cache_dir)
    : root_(std::move(root)), cache_dir_(cache_dir ? *cache_dir : default_cache_dir() / "shaders") {
  if (root_.empty()) root_ = repo_root() / "shaders";
  root_ = fs::weakly_canonical(root_);
}

fs::path ShaderCompiler::resolve(const fs::path& p) const {
  if (p.is_absolute()) return p.lexically_normal();
  return (root_ / p).lexically_normal();
}

std::string ShaderCompiler::display_name(const fs::path& abs) const {
  fs::path rel = abs.lexically_relative(root_);
  if (!rel.empty() && *rel.begin() != "..") return (root_.filename() / rel).generic_string();
  return abs.generic_string();
}

std::optional<fs::path> ShaderCompiler::resolve_include(const std::string& name, const fs::path& includer) const {
  fs::path local = (includer.parent_path() / name).lexically_normal();
  if (fs::is_regular_file(local)) return local;
  fs::path global = (root_ / name).lexically_normal();
  if (fs::is_regular_file(global)) return global;
  return std::nullopt;
}

namespace {

// Scans #include lines (a superset of what the preprocessor will include: lines inside #if blocks
// count too) to build the cache key before compiling.
void gather_sources(const ShaderCompiler& c, const fs::path& file, std::vector<fs::path>& order,
                    std::set<fs::path>& seen, uint64_t& key) {
  if (!seen.insert(file).second) return;
  order.push_back(file);
  std::string text = read_file_text(file);
  key = hash64(text, hash64(file.generic_string(), key));
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    size_t p = line.find_first_not_of(" \t");
    if (p == std::string::npos || line[p] != '#') continue;
    p = line.find_first_not_of(" \t", p + 1);
    if (p == std::string::npos || line.compare(p, 7, "include") != 0) continue;
    size_t open = line.find_first_of("\"<", p + 7);
    if (open == std::string::npos) continue;
    size_t close = line.find_first_of("\">", open + 1);
    if (close == std::string::npos) continue;
    std::string name = line.substr(open + 1, close - open - 1);
    if (auto resolved = c.resolve_include(name, file))
      gather_sources(c, *resolved, order, seen, key);
    else
      key = hash64("missing:" + name, key);
  }
}

class Includer : public glslang::TShader::Includer {
 public:
  Includer(const ShaderCompiler& c, fs::path main, std::string main_display) : c_(c) {
    by_display_[main_display] = std::move(main);
  }
  IncludeResult* includeLocal(const char* name, const char* includer, size_t depth) override {
    return include(name, includer);
  }
  IncludeResult* includeSystem(const char* name, const char* includer, size_t depth) override {
    return include(name, includer);
  }
  void releaseInclude(IncludeResult* r) override {
    if (!r) return;
    delete static_cast<std::string*>(r->userData);
    delete r;
  }
  std::vector<fs::path> included;

 private:
  IncludeResult* include(const char* name, const char* includer) {
    fs::path includer_path;
    if (auto it = by_display_.find(includer ? includer : ""); it != by_display_.end())
      includer_path = it->second;
    else
      includer_path = c_.root() / "main";
    auto resolved = c_.resolve_include(name, includer_path);
    if (!resolved) {
      auto* msg = new std::string(strf("cannot find include \"%s\" (searched %s and %s)", name,
                                       c_.display_name(includer_path.parent_path()).c_str(),
                                       c_.display_name(c_.root()).c_str()));
      return new IncludeResult("", msg->c_str(), msg->size(), msg);
    }
    auto* text = new std::string(read_file_text(*resolved));
    std::string display = c_.display_name(*resolved);
    by_display_[display] = *resolved;
    included.push_back(*resolved);
    return new IncludeResult(display, text->c_str(), text->size(), text);
  }
  const ShaderCompiler& c_;
  std::map<std::string, fs::path> by_display_;
};

// glslang logs "ERROR: shaders/x.comp:12: 'foo' : undeclared identifier"; we keep "FILE:LINE: message"
// lines and drop the summary ("N compilation errors. No code generated.").
std::string format_log(const std::string& log, const std::string& display) {
  static const std::regex located(R"(^[^\s:][^:]*:[0-9]+: )");
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    for (const char* prefix :
         {"ERROR: ", "WARNING: ", "Linking compute stage: ", "Linking vertex stage: ", "Linking fragment stage: "})
      if (line.rfind(prefix, 0) == 0) line = line.substr(std::strlen(prefix));
    if (line.empty() || line.find("compilation errors.") != std::string::npos) continue;
    if (!std::regex_search(line, located)) line = display + ": " + line;
    out += line + "\n";
  }
  if (out.empty()) out = display + ": compilation failed\n";
  out.pop_back();
  return out;
}

}  // namespace

CompiledShader ShaderCompiler::compile(const fs::path& path, const std::vector<ShaderDefine>& defines,
                                       std::optional<ShaderStage> stage_opt) const {
  fs::path abs = resolve(path);
  CompiledShader out;
  out.display_name = display_name(abs);
  auto stage = stage_opt ? stage_opt : stage_from_path(abs);
  if (!stage) fail("%s: unknown shader stage (use .vert, .frag or .comp)", out.display_name.c_str());
  out.stage = *stage;
  if (!fs::is_regular_file(abs)) fail("%s: shader file not found", out.display_name.c_str());

  std::string preamble;
  for (const auto& d : defines) preamble += "#define " + d.name + " " + d.value + "\n";
  std::set<fs::path> seen;
  uint64_t key = hash64(strf("v1 %s spv1.6 vk1.3\n", stage_name(*stage)));
  key = hash64(preamble, key);
  gather_sources(*this, abs, out.files, seen, key);
  out.key = key;

  fs::path cache_file;
  if (!cache_dir_.empty()) {
    cache_file = cache_dir_ / strf("%016llx.spv", (unsigned long long)key);
    std::ifstream in(cache_file, std::ios::binary);
    if (in) {
      std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      uint32_t magic = 0;
      if (bytes.size() >= 20 && bytes.size() % 4 == 0 && (std::memcpy(&magic, bytes.data(), 4), magic == 0x07230203u)) {
        out.spirv.resize(bytes.size() / 4);
        std::memcpy(out.spirv.data(), bytes.data(), bytes.size());
        out.from_cache = true;
        std::lock_guard lock(g_glslang_mutex);  // counters are shared by threads compiling at once
        cache_hits++;
        return out;
      }
      LOG_WARN("gpu: ignoring corrupt shader cache file %s", cache_file.string().c_str());
    }
  }

  std::string source = read_file_text(abs);
  {
    std::lock_guard lock(g_glslang_mutex);
    init_glslang();
    EShLanguage lang = to_glslang(*stage);
    glslang::TShader shader(lang);
    const char* src = source.c_str();
    int len = int(source.size());
    const char* name = out.display_name.c_str();
    shader.setStringsWithLengthsAndNames(&src, &len, &name, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEntryPoint("main");
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_3);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_6);
    Includer includer(*this, abs, out.display_name);
    auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 460, false, messages, includer))
      throw Error(format_log(shader.getInfoLog(), out.display_name));
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) throw Error(format_log(program.getInfoLog(), out.display_name));
    glslang::SpvOptions options;
    options.disableOptimizer = true;  // drivers optimize anyway; keeps compiles at a few ms for hot reload
    spv::SpvBuildLogger logger;
    glslang::GlslangToSpv(*program.getIntermediate(lang), out.spirv, &logger, &options);
    std::string msgs = logger.getAllMessages();
    if (!msgs.empty()) LOG_DEBUG("%s: %s", out.display_name.c_str(), msgs.c_str());
    compiles++;
  }

  if (!cache_file.empty()) {
    std::error_code ec;
    fs::create_directories(cache_dir_, ec);
    fs::path tmp = cache_file;
    tmp += ".tmp" + std::to_string(::getpid());
    {
      std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
      o.write(reinterpret_cast<const char*>(out.spirv.data()), std::streamsize(out.spirv.size() * 4));
    }
    fs::rename(tmp, cache_file, ec);
    if (ec) {
      LOG_WARN("gpu: cannot write shader cache %s: %s", cache_file.string().c_str(), ec.message().c_str());
      fs::remove(tmp, ec);
    }
  }
  return out;
}

}  // namespace cumulo::gpu
