// TGA-slice import and the parts every importer shares (NVDFs from an SDF, saving).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/message.h"
#include "engine/core/log.h"
#include "engine/core/memory_budget.h"
#include "engine/core/parallel.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/tga.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {

namespace fs = std::filesystem;

CloudscapeVolumes nvdfs_from_sdf(const std::vector<float>& sdf, glm::uvec3 size, float voxel_size,
                                 glm::vec3 bounds_min, const DeriveOptions& derive) {
  if (sdf.size() != size_t(size.x) * size.y * size.z) fail("nvdfs_from_sdf: %zu values for %ux%ux%u", sdf.size(), size.x, size.y, size.z);
  CloudscapeVolumes out{make_modeling_volume(size, voxel_size, bounds_min), make_field_volume(size, voxel_size, bounds_min)};
  const uint32_t cp = out.modeling.channel(kDimensionalProfile, "modeling");
  const uint32_t cd = out.modeling.channel(kDetailType, "modeling");
  const uint32_t cs = out.modeling.channel(kDensityScale, "modeling");
  if (out.modeling.encoding != VolumeEncoding::RGBA8 || out.field.encoding != VolumeEncoding::R16 ||
      out.field.channel(kSignedDistance, "field") != 0)
    fail("nvdfs_from_sdf: NVDF layouts changed (nvdf.h)");
  auto unorm8 = [](float v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  const uint8_t detail = unorm8(derive.detail_type), density = unorm8(derive.density_scale);
  uint8_t* modeling = out.modeling.levels[0].data();
  uint8_t* field = out.field.levels[0].data();
  parallel_for(sdf.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const float d = sdf[i];
      const float p = dimensional_profile_from_sdf(d, derive.profile_depth_m, derive.profile_exponent);
      uint8_t* m = modeling + 4 * i;
      m[cp] = unorm8(p);
      // Detail type and density scale only matter inside; outside they stay 0 so that the
      // texture compresses well and bilinear filtering at the edge fades them with the profile.
      m[cd] = p > 0.0f ? detail : 0;
      m[cs] = p > 0.0f ? density : 0;
      const uint16_t q = sdf_to_unorm16_floor(d);
      field[2 * i] = uint8_t(q & 0xff);
      field[2 * i + 1] = uint8_t(q >> 8);
    }
  }, 4096);
  return out;
}

void save_cloudscape(const fs::path& dir, const CloudscapeVolumes& v, bool compress) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) fail("%s: cannot create folder: %s", dir.string().c_str(), ec.message().c_str());
  save_volume(dir / kModelingFileName, v.modeling, {.compress = compress});
  save_volume(dir / kFieldFileName, v.field, {.compress = compress});
}

uint32_t parse_channel_letter(const std::string& s) {
  std::string l = s;
  for (auto& c : l) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (l == "r" || l == "0") return 0;
  if (l == "g" || l == "1") return 1;
  if (l == "b" || l == "2") return 2;
  if (l == "a" || l == "3") return 3;
  fail("channel %s: expected r, g, b or a", quote(s, 16).c_str());
}

std::vector<fs::path> numbered_slices(const fs::path& dir) {
  const std::string d = dir.string();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) fail("%s: not a folder (or missing)", d.c_str());
  struct Entry {
    unsigned long long number;
    fs::path path;
  };
  std::vector<Entry> entries;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".tga") continue;
    const std::string stem = e.path().stem().string();
    // The last run of digits is the slice number ("cloud_v2_slice_010" -> 10).
    size_t end = stem.size();
    while (end > 0 && !std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
    size_t begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
    if (begin == end) fail("%s: slice file name has no number (cannot order the z slices)", e.path().string().c_str());
    if (end - begin > 9) fail("%s: slice number '%s' is too long", e.path().string().c_str(), stem.substr(begin, end - begin).c_str());
    entries.push_back({std::stoull(stem.substr(begin, end - begin)), e.path()});
  }
  if (ec) fail("%s: cannot list folder: %s", d.c_str(), ec.message().c_str());
  if (entries.empty()) fail("%s: no .tga slices in folder", d.c_str());
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.number != b.number ? a.number < b.number : a.path < b.path;
  });
  for (size_t i = 1; i < entries.size(); ++i)
    if (entries[i].number == entries[i - 1].number)
      fail("%s: slice number %llu also used by %s", entries[i].path.string().c_str(), entries[i].number,
           entries[i - 1].path.filename().string().c_str());
  std::vector<fs::path> out;
  for (auto& e : entries) out.push_back(std::move(e.path));
  return out;
}

namespace {

struct SliceStack {
  glm::uvec3 size{0};
  std::vector<Rgba8Image> slices;
  std::string first;  // file that set the size, for messages
};

SliceStack load_stack(const fs::path& dir) {
  SliceStack s;
  const std::vector<fs::path> files = numbered_slices(dir);
  if (files.size() > 4096) fail("%s: %zu slices (at most 4096)", dir.string().c_str(), files.size());
  // Decoded RGBA (4 bytes a pixel) plus the volumes derived from it (about 56 bytes a voxel, as a
  // VDB import): budgeted from the headers before anything is decoded.
  uint64_t pixels = 0, largest = 0;
  for (const fs::path& f : files) {
    const auto [w, h] = peek_tga_size(f, {.max_dimension = 4096});
    pixels += uint64_t(w) * h;
    largest = std::max(largest, uint64_t(w) * h);
  }
  check_memory_budget(saturating_product({pixels, 4}) + saturating_product({largest, files.size(), 56}),
                      strf("%s: %zu TGA slices of up to %llu pixels", dir.string().c_str(), files.size(),
                           static_cast<unsigned long long>(largest)));
  s.slices.resize(files.size());
  // Decode in parallel (TGA decode dominates), then check sizes in order so the first mismatch is named.
  parallel_for(files.size(), [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) s.slices[i] = load_tga(files[i], {.max_dimension = 4096});
  });
  s.first = files[0].string();
  s.size = {s.slices[0].width, s.slices[0].height, uint32_t(files.size())};
  for (size_t i = 1; i < files.size(); ++i)
    if (s.slices[i].width != s.size.x || s.slices[i].height != s.size.y)
      fail("%s: slice is %ux%u, but %s is %ux%u (all slices must match)", files[i].string().c_str(),
           s.slices[i].width, s.slices[i].height, files[0].filename().string().c_str(), s.size.x, s.size.y);
  return s;
}

// Volume size of a stack of `n` W x H slices, and the slice pixel of volume texel (x, y, z); see
// SliceAxis in import.h.
glm::uvec3 volume_size(glm::uvec3 stack, SliceAxis axis) {
  return axis == SliceAxis::Y ? glm::uvec3(stack.x, stack.z, stack.y) : stack;
}
uint8_t component(const SliceStack& s, SliceAxis axis, uint32_t x, uint32_t y, uint32_t z, uint32_t c) {
  if (axis == SliceAxis::Y) return s.slices[y].pixel(x, z)[c];
  return s.slices[z].pixel(x, s.size.y - 1 - y)[c];
}

}  // namespace

CloudscapeVolumes import_tga_slices(const std::optional<fs::path>& modeling_dir, const std::optional<fs::path>& field_dir,
                                    const SliceImportOptions& o) {
  if (!modeling_dir && !field_dir) fail("import: give a modeling folder, a field folder or both");
  if (!(o.voxel_size > 0.0f) || !std::isfinite(o.voxel_size)) fail("import: voxel size %g must be positive", o.voxel_size);
  if (!(o.sdf_max > o.sdf_min)) fail("import: SDF range %g..%g is empty", o.sdf_min, o.sdf_max);
  for (uint32_t c : {o.profile_channel, o.detail_channel, o.density_channel, o.sdf_channel})
    if (c > 3) fail("import: channel index %u (0..3)", c);

  Stopwatch clock;
  std::optional<SliceStack> modeling, field;
  if (modeling_dir) modeling = load_stack(*modeling_dir);
  if (field_dir) field = load_stack(*field_dir);
  LOG_DEBUG("import: slices read %.2f s", clock.seconds());
  if (modeling && field && modeling->size != field->size)
    fail("%s: field slices are %ux%ux%u, modeling slices (%s) are %ux%ux%u", field_dir->string().c_str(), field->size.x,
         field->size.y, field->size.z, modeling_dir->string().c_str(), modeling->size.x, modeling->size.y,
         modeling->size.z);
  const glm::uvec3 size = volume_size(modeling ? modeling->size : field->size, o.axis);
  const size_t count = size_t(size.x) * size.y * size.z;
  auto index = [&](uint32_t x, uint32_t y, uint32_t z) { return (size_t(z) * size.y + y) * size.x + x; };

  // Signed distance in metres: from the field slices, else from the modeling profile's support.
  std::vector<float> sdf(count);
  if (field) {
    const float scale = (o.sdf_max - o.sdf_min) / 255.0f;
    for (uint32_t z = 0; z < size.z; ++z)
      for (uint32_t y = 0; y < size.y; ++y)
        for (uint32_t x = 0; x < size.x; ++x)
          sdf[index(x, y, z)] = o.sdf_min + scale * float(component(*field, o.axis, x, y, z, o.sdf_channel));
  } else {
    std::vector<uint8_t> inside(count);
    for (uint32_t z = 0; z < size.z; ++z)
      for (uint32_t y = 0; y < size.y; ++y)
        for (uint32_t x = 0; x < size.x; ++x) inside[index(x, y, z)] = component(*modeling, o.axis, x, y, z, o.profile_channel) > 0;
    sdf = signed_distance_from_mask(inside, size, o.voxel_size);
  }
  const glm::vec3 extent = glm::vec3(size) * o.voxel_size;
  const glm::vec3 origin = o.origin ? *o.origin : glm::vec3(-0.5f * extent.x, 0.0f, -0.5f * extent.z);
  LOG_DEBUG("import: distances %.2f s", clock.seconds());
  CloudscapeVolumes out = nvdfs_from_sdf(sdf, size, o.voxel_size, origin, o.derive);
  LOG_DEBUG("import: NVDFs %.2f s", clock.seconds());

  if (modeling) {  // the authored modeling data replaces the derived defaults, byte for byte
    Volume& m = out.modeling;
    const uint32_t cp = m.channel(kDimensionalProfile, "modeling"), cd = m.channel(kDetailType, "modeling"),
                   cs = m.channel(kDensityScale, "modeling");
    if (m.encoding != VolumeEncoding::RGBA8) fail("import: modeling layout changed");
    parallel_for(size.z, [&](size_t z0, size_t z1) {
      for (uint32_t z = uint32_t(z0); z < z1; ++z)
        for (uint32_t y = 0; y < size.y; ++y)
          for (uint32_t x = 0; x < size.x; ++x) {
            uint8_t* t = &m.levels[0][index(x, y, z) * 4];  // 8-bit to 8-bit: copied exactly
            t[cp] = component(*modeling, o.axis, x, y, z, o.profile_channel);
            t[cd] = component(*modeling, o.axis, x, y, z, o.detail_channel);
            t[cs] = component(*modeling, o.axis, x, y, z, o.density_channel);
          }
    });
  }
  LOG_INFO("import: %ux%ux%u slices at %g m (%s%s%s)", size.x, size.y, size.z, o.voxel_size, modeling ? "modeling" : "",
           modeling && field ? " + " : "", field ? "field" : "");
  return out;
}

}  // namespace cumulo::clouds
