#include "modules/clouds/grow_gpu/grown_asset_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/readback.h"
#include "engine/gpu/timestamps.h"
#include "modules/clouds/bake/grow/grow_spec.h"
#include "modules/clouds/bake/grow/grown_attributes.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/grow_gpu/grow_dispatch.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds::grow_gpu {

namespace {

constexpr VkFormat kModelingFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kFieldFormat = VK_FORMAT_R16_UNORM;
// grown_attributes.cpp's percentile floors: max(percentile, floor) for |condensation|, |w|, |growth|, the median.
constexpr float kFloors[GROWN_QUANTITIES] = {1e-12f, 1e-6f, 1e-14f, 1e-9f};
constexpr float kQuantiles[GROWN_QUANTITIES] = {0.9f, 0.9f, 0.9f, 0.5f};
constexpr int kDilationRings = 4;  // grown_attributes.cpp's dilate(..., 4, 0.5)

gpu::Buffer storage(gpu::Context& ctx, size_t bytes, const char* name) {
  return gpu::Buffer(ctx,
                     {std::max<size_t>(bytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::GpuOnly, name});
}

gpu::Image storage_image(gpu::Context& ctx, glm::ivec3 d, VkFormat format, const char* name) {
  VkFormatProperties props{};
  vkGetPhysicalDeviceFormatProperties(ctx.physical_device(), format, &props);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
  if ((props.optimalTilingFeatures & need) != need)
    fail("grow_gpu: %s cannot be a linearly sampled storage image on %s (%s)", name, ctx.info().name.c_str(),
         format == kFieldFormat ? "R16 unorm" : "RGBA8 unorm");
  return gpu::Image(ctx, gpu::ImageDesc::tex3d(uint32_t(d.x), uint32_t(d.y), uint32_t(d.z), format,
                                               VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                                   VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                               1, name));
}

}  // namespace

GrownAssetSettings grown_asset_settings(const grow::GrowSpec& spec, float voxel_size) {
  GrownAssetSettings s;
  s.cell_game = spec.cell_game;
  s.iso = spec.iso;
  s.voxel_size = voxel_size;
  return s;
}

GrownAssetGrid grown_asset_grid(glm::ivec3 cells, const GrownAssetSettings& s) {
  if (!(s.cell_game > 0.0f) || !(s.voxel_size > 0.0f))
    fail("grow_gpu: a grown asset needs a cell and a voxel size > 0 (got %g and %g m)", s.cell_game, s.voxel_size);
  GrownAssetGrid g;
  g.cells = cells;
  g.per_cell = std::max(1, int(std::ceil(s.cell_game / s.voxel_size - 1e-4f)));  // derive_modeling's f
  g.voxel = s.cell_game / float(g.per_cell);
  g.voxels = (cells - 1) * g.per_cell + 1;
  g.origin = s.default_origin ? glm::vec3((0.5f - 0.5f * float(cells.x)) * s.cell_game, 0.5f * s.cell_game,
                                          (0.5f - 0.5f * float(cells.z)) * s.cell_game)
                              : s.origin;
  g.bounds_min = g.origin - 0.5f * g.voxel;
  g.bounds_max = g.origin + (glm::vec3(g.voxels) - 0.5f) * g.voxel;
  return g;
}

GpuGrownAsset::GpuGrownAsset(gpu::Context& ctx, gpu::PipelineLibrary& library, glm::ivec3 cells,
                             const GrownAssetSettings& settings)
    : ctx_(ctx),
      s_(settings),
      grid_(grown_asset_grid(cells, settings)),
      params_(ctx, {sizeof(shared::GrownAssetParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                    "grown_asset.params"}) {
  const glm::ivec3 n = grid_.voxels;
  if (cells.x < 2 || cells.y < 2 || cells.z < 2)
    fail("grow_gpu: a grown asset needs at least 2 cells per axis (got %dx%dx%d)", cells.x, cells.y, cells.z);
  if (n.x > GROWN_MAX_VOXELS_PER_AXIS || n.y > GROWN_MAX_VOXELS_PER_AXIS || n.z > GROWN_MAX_VOXELS_PER_AXIS)
    fail("grow_gpu: a grown asset of %dx%dx%d voxels (%g m) has more than %d along an axis: raise the voxel size", n.x,
         n.y, n.z, grid_.voxel, GROWN_MAX_VOXELS_PER_AXIS);
  auto pipe = [&](const char* shader, const char* name) {
    return &library.compute({.shader = std::string("clouds/grow/") + shader, .name = name});
  };
  pipes_.resample = pipe("sdf_resample.comp", "grown.sdf_resample");
  pipes_.jfa = pipe("sdf_jfa.comp", "grown.sdf_jfa");
  pipes_.distance = pipe("sdf_distance.comp", "grown.sdf_distance");
  pipes_.store_field = pipe("sdf_store.comp", "grown.sdf_store");
  pipes_.histogram = pipe("attr_histogram.comp", "grown.attr_histogram");
  pipes_.select = pipe("attr_select.comp", "grown.attr_select");
  pipes_.column = pipe("attr_column.comp", "grown.attr_column");
  pipes_.rates = pipe("attr_rates.comp", "grown.attr_rates");
  pipes_.dilate = pipe("attr_dilate.comp", "grown.attr_dilate");
  pipes_.blur = pipe("attr_blur.comp", "grown.attr_blur");
  pipes_.depth = pipe("attr_depth.comp", "grown.attr_depth");
  pipes_.store_modeling = pipe("attr_store.comp", "grown.attr_store");

  const size_t voxels = grid_.count(), cell_count = size_t(cells.x) * cells.y * cells.z;
  fine_ = storage(ctx, voxels * sizeof(float), "grown.cloud_water resampled");
  seeds_a_ = storage(ctx, voxels * sizeof(uint32_t), "grown.seeds a / depth a");
  seeds_b_ = storage(ctx, voxels * sizeof(uint32_t), "grown.seeds b / depth b");
  distance_ = storage(ctx, voxels * sizeof(float), "grown.distance");
  select_ = storage(ctx, (GROWN_SELECT_HEADER + GROWN_QUANTITIES * GROWN_BINS) * sizeof(uint32_t), "grown.select");
  columns_ = storage(ctx, size_t(cells.x) * cells.z * sizeof(glm::ivec2), "grown.columns");
  attributes_a_ = storage(ctx, cell_count * sizeof(glm::vec4), "grown.attributes a");
  attributes_b_ = storage(ctx, cell_count * sizeof(glm::vec4), "grown.attributes b");

  // Jump flooding: N/2, N/4, ..., 1 for N the power of two at or above the longest axis, then the extra passes
  // (3: steps 4, 2, 1).
  int top = 1;
  while (top < std::max(n.x, std::max(n.y, n.z))) top *= 2;
  for (int k = top / 2; k >= 1; k /= 2) jfa_steps_.push_back(k);
  if (s_.flood_extra_passes < 0 || s_.flood_extra_passes > 8)
    fail("grow_gpu: flood_extra_passes %d is outside 0..8", s_.flood_extra_passes);
  if (s_.flood_extra_passes > 0)
    for (int k = 1 << (s_.flood_extra_passes - 1); k >= 1; k /= 2) jfa_steps_.push_back(k);

  shared::GrownAssetParams p{};
  p.cells = glm::ivec4(cells, int(cell_count));
  p.voxels = glm::ivec4(n, int(voxels));
  p.grid = glm::vec4(float(grid_.per_cell), grid_.voxel, s_.iso, 0.5f * grid_.voxel);
  if (!(s_.safety_margin >= 0.0f) || !(s_.safety_fraction >= 0.0f) || !(s_.safety_fraction < 1.0f))
    fail("grow_gpu: the field's safety margin must be >= 0 m and its fraction in [0, 1) (got %g m, %g)",
         s_.safety_margin, s_.safety_fraction);
  p.field = glm::vec4(kSdfRangeMin, kSdfRangeMax, s_.safety_fraction, s_.safety_margin);
  p.profile = glm::vec4(grow::kThicknessFactor, grow::kMinProfileDepth, grow::kMaxProfileDepth, s_.profile_exponent);
  p.detail = glm::vec4(grow::kGrowthWeight, grow::kCondensationWeight, grow::kUpdraftWeight, grow::kHeightWeight);
  p.quantiles = glm::vec4(kQuantiles[0], kQuantiles[1], kQuantiles[2], kQuantiles[3]);
  p.floors = glm::vec4(kFloors[0], kFloors[1], kFloors[2], kFloors[3]);
  // derive_modeling's thickness radius in voxels.
  p.radii = glm::ivec4(std::max(1, int(std::ceil(grow::kThicknessRadius / grid_.voxel))), 0, 0, 0);
  p.coverage = glm::vec4(std::clamp(s_.coverage, 0.0f, 1.0f), 0.0f, 0.0f, 0.0f);
  std::memcpy(params_.mapped(), &p, sizeof p);

  modeling_ = storage_image(ctx, n, kModelingFormat, "grown.modeling");
  field_ = storage_image(ctx, n, kFieldFormat, "grown.field");
  // No fair-weather field: one texel at the decode minimum (cloud_assets.cpp's stand-in).
  field_fair_ = gpu::Image(
      ctx, gpu::ImageDesc::tex3d(1, 1, 1, kFieldFormat, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "grown.field_fair (none)"));
  const uint16_t inside = 0;
  field_fair_.upload({gpu::MipData{&inside, sizeof inside}});
  clear_images();
}

GpuGrownAsset::~GpuGrownAsset() = default;

GrownAssetView GpuGrownAsset::view() const {
  GrownAssetView v;
  v.modeling = &modeling_, v.field = &field_, v.field_fair = &field_fair_;
  v.dims = glm::uvec3(grid_.voxels);
  v.voxel_size = grid_.voxel;
  v.bounds_min = grid_.bounds_min, v.bounds_max = grid_.bounds_max;
  v.gpu_bytes = uint64_t(grid_.count()) * (4 + 2);
  return v;
}

// Before the first update: no cloud (the field's maximum everywhere, modeling 0), ready to sample.
void GpuGrownAsset::clear_images() {
  ctx_.submit_and_wait([&](VkCommandBuffer cmd) {
    for (gpu::Image* img : {&field_, &modeling_}) {
      img->cmd_transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
      const VkClearColorValue value = {{img == &field_ ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f}};
      const VkImageSubresourceRange range = img->full_range();
      vkCmdClearColorImage(cmd, img->handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1, &range);
      img->cmd_transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
  });
}

uint32_t GpuGrownAsset::voxel_groups() const {
  return uint32_t((grid_.count() + GROWN_LOCAL_SIZE - 1) / GROWN_LOCAL_SIZE);
}
uint32_t GpuGrownAsset::cell_groups() const {
  const size_t cells = size_t(grid_.cells.x) * grid_.cells.y * grid_.cells.z;
  return uint32_t((cells + GROWN_LOCAL_SIZE - 1) / GROWN_LOCAL_SIZE);
}

// The parameter block at binding 0, the buffers from binding 1 in the order given, the images at their bindings
// (those the shader declares), the push constants; then `groups` work groups.
void GpuGrownAsset::pass(VkCommandBuffer cmd, const gpu::Pipeline& pipe, const std::vector<VkBuffer>& buffers,
                         uint32_t groups, int pass_x, int axis, int radix) const {
  pipe.bind(cmd);
  gpu::DescriptorWriter writer;
  if (pipe.find_binding(0, GROWN_BINDING_PARAMS)) writer.uniform_buffer(GROWN_BINDING_PARAMS, params_.handle());
  uint32_t binding = GROWN_BINDING_PARAMS + 1;
  for (VkBuffer b : buffers) {
    if (pipe.find_binding(0, binding)) writer.storage_buffer(binding, b);
    ++binding;
  }
  if (pipe.find_binding(0, GROWN_BINDING_FIELD_IMAGE))
    writer.storage_image(GROWN_BINDING_FIELD_IMAGE, field_.view(), VK_IMAGE_LAYOUT_GENERAL);
  if (pipe.find_binding(0, GROWN_BINDING_MODELING_IMAGE))
    writer.storage_image(GROWN_BINDING_MODELING_IMAGE, modeling_.view(), VK_IMAGE_LAYOUT_GENERAL);
  for (const gpu::PipelineBinding& b : pipe.bindings())
    if (b.set == 0 && b.binding >= binding && b.binding != GROWN_BINDING_FIELD_IMAGE &&
        b.binding != GROWN_BINDING_MODELING_IMAGE)
      fail("grow_gpu: pass '%s' declares binding %u, not given", pipe.name().c_str(), b.binding);
  writer.push(ctx_, cmd, pipe);
  const shared::GrownAssetPush push{glm::ivec4(pass_x, axis, radix, 0)};
  if (pipe.push_constant_size() >= sizeof(push)) pipe.push_constants(cmd, push);
  vkCmdDispatch(cmd, groups, 1, 1);
}

// The update as barrier intervals. Each stage's passes touch no buffer another pass of the same stage writes; a
// barrier follows every stage but the last. Only the last stage writes the images, so an update spread over frames
// (record_update_stages) leaves the images whole until its last frame; the stages before it read the solver's buffers
// and write the scratch buffers only.
const std::vector<GpuGrownAsset::Stage>& GpuGrownAsset::stages(const GpuCloudSolver& solver,
                                                                GrownUpdateOrder order) const {
  StageCache& c = stage_cache_[size_t(order)];
  const std::array<VkBuffer, 4> reads = {solver.buffer(Field::CloudWater), solver.buffer(Field::Condensation),
                                          solver.buffer(Field::Growth), solver.buffer(Field::V)};
  if (c.list.empty() || c.solver != reads || solver.dims() != grid_.cells) {
    c.list = build_stages(solver, order);
    c.solver = reads;
  }
  return c.list;
}

std::vector<GpuGrownAsset::Stage> GpuGrownAsset::build_stages(const GpuCloudSolver& solver,
                                                              GrownUpdateOrder order) const {
  if (solver.dims() != grid_.cells)
    fail("grow_gpu: a grown asset for %dx%dx%d cells updated from a %dx%dx%d solver", grid_.cells.x, grid_.cells.y,
         grid_.cells.z, solver.dims().x, solver.dims().y, solver.dims().z);
  const VkBuffer qc = solver.buffer(Field::CloudWater), cond = solver.buffer(Field::Condensation),
                 growth = solver.buffer(Field::Growth), v = solver.buffer(Field::V);
  const uint32_t vg = voxel_groups(), cg = cell_groups();
  // The cost estimate: work groups x the texels a thread reads (the flood's and the conservative store's 27, the
  // depth filter's 2r + 1); what spreading an update over frames balances.
  const float fv = float(vg), fc = float(cg);
  const float depth_taps = float(2 * std::max(1, int(std::ceil(grow::kThicknessRadius / grid_.voxel))) + 1);

  std::vector<Stage> list(1);
  auto add = [&](float cost, std::function<void(VkCommandBuffer)> record) {
    list.back().cost += cost;
    list.back().passes.push_back(std::move(record));
  };
  auto barrier = [&] { list.emplace_back(); };
  auto range = [&](const char* name) { list.back().range = name; };
  auto P = [this](const gpu::Pipeline* pipe, std::vector<VkBuffer> buffers, uint32_t groups, int pass_x = 0,
                  int axis = 0, int radix = 0) {
    return [=, this](VkCommandBuffer cmd) { pass(cmd, *pipe, buffers, groups, pass_x, axis, radix); };
  };

  const uint32_t histogram_groups = uint32_t(
      (size_t(grid_.cells.x) * grid_.cells.y * grid_.cells.z + GROWN_HISTOGRAM_CELLS - 1) / GROWN_HISTOGRAM_CELLS);
  // The percentiles' radix select: a select after each histogram, four of each.
  struct RadixStep {
    const gpu::Pipeline* pipe;
    int radix;
  };
  const RadixStep radix_steps[] = {{pipes_.select, 0}, {pipes_.histogram, 1}, {pipes_.select, 1}, {pipes_.histogram, 2},
                                   {pipes_.select, 2}, {pipes_.histogram, 3}, {pipes_.select, 3}};
  auto radix_step = [&](const RadixStep& r) {
    if (r.pipe == pipes_.select)
      add(0.0f, P(r.pipe, {select_.handle()}, 1, 0, 0, r.radix));
    else
      add(4.0f * float(histogram_groups), P(r.pipe, {qc, cond, growth, v, select_.handle()}, histogram_groups, 0, 0, r.radix));
  };
  auto columns_and_histogram = [&] {
    add(float(grid_.cells.y), P(pipes_.column, {qc, columns_.handle()},
                                uint32_t((grid_.cells.x * grid_.cells.z + GROWN_LOCAL_SIZE - 1) / GROWN_LOCAL_SIZE)));
    add(4.0f * float(histogram_groups), P(pipes_.histogram, {qc, cond, growth, v, select_.handle()}, histogram_groups, 0, 0, 0));
  };
  auto rates = [&] {
    add(8.0f * fc, P(pipes_.rates, {qc, cond, growth, v, select_.handle(), columns_.handle(), attributes_a_.handle()}, cg));
  };
  // The profile depth (x, y, z max filters of the distance: -> a -> b -> a) beside the attributes' dilation (4 rings)
  // and blur (3 axes); the images after them, in the last stage.
  VkBuffer attributes = VK_NULL_HANDLE;
  auto depth_dilate_blur = [&] {
    VkBuffer a = attributes_a_.handle(), b = attributes_b_.handle();
    add(depth_taps * fv, P(pipes_.depth, {distance_.handle(), seeds_a_.handle()}, vg, 0, 0));
    add(27.0f * fc, P(pipes_.dilate, {a, b}, cg));
    std::swap(a, b);
    barrier();
    add(depth_taps * fv, P(pipes_.depth, {seeds_a_.handle(), seeds_b_.handle()}, vg, 0, 1));
    for (int ring = 1; ring < kDilationRings; ++ring) {
      add(27.0f * fc, P(pipes_.dilate, {a, b}, cg));
      std::swap(a, b);
      barrier();
    }
    add(depth_taps * fv, P(pipes_.depth, {seeds_b_.handle(), seeds_a_.handle()}, vg, 0, 2));
    for (int axis = 0; axis < 3; ++axis) {
      add(8.0f * fc, P(pipes_.blur, {a, b}, cg, 0, axis));
      std::swap(a, b);
      barrier();
    }
    attributes = a;  // (the blur's last barrier opened the images' stage)
  };
  VkBuffer from = seeds_a_.handle(), to = seeds_b_.handle();
  auto flood_step = [&](size_t i) {
    add(27.0f * fv, P(pipes_.jfa, {from, to}, vg, jfa_steps_[i]));
    std::swap(from, to);
  };
  // The histograms start at zero; the fill follows the solver's steps recorded before (the barrier after it).
  add(0.0f, [this](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, select_.handle(), 0, VK_WHOLE_SIZE, 0u); });

  if (order == GrownUpdateOrder::Apart) {
    // For `cumulo bench`: the distance field, then the attributes, each in its own timer range (the same work and
    // the same bytes as the interleaved order, more barrier intervals).
    barrier();
    range("grown.sdf");
    add(8.0f * fv, P(pipes_.resample, {qc, fine_.handle(), seeds_a_.handle()}, vg));
    barrier();
    for (size_t i = 0; i < jfa_steps_.size(); ++i) {
      flood_step(i);
      barrier();
    }
    add(7.0f * fv, P(pipes_.distance, {from, fine_.handle(), distance_.handle()}, vg));
    barrier();
    range("grown.attributes");
    columns_and_histogram();
    barrier();
    for (const RadixStep& r : radix_steps) {
      radix_step(r);
      barrier();
    }
    rates();
    barrier();
    depth_dilate_blur();
  } else {
    // The distance: resample and classify, jump flooding, the distance and the iso-crossing. The attributes' passes
    // on the cells run beside it (they read the solver's buffers only): each radix step shares a barrier interval
    // with one flood pass (they touch different buffers).
    range("grown.classify");
    barrier();
    add(8.0f * fv, P(pipes_.resample, {qc, fine_.handle(), seeds_a_.handle()}, vg));
    columns_and_histogram();
    barrier();
    range("grown.flood");
    const size_t steps = std::max(jfa_steps_.size(), std::size(radix_steps));
    for (size_t i = 0; i < steps; ++i) {
      if (i < jfa_steps_.size()) flood_step(i);
      if (i < std::size(radix_steps)) radix_step(radix_steps[i]);
      barrier();
    }
    range("grown.distance");
    add(7.0f * fv, P(pipes_.distance, {from, fine_.handle(), distance_.handle()}, vg));
    rates();
    barrier();
    range("grown.store");
    depth_dilate_blur();
  }
  // The images: their old contents discarded (every texel is written), then sampled from here on (the march, the
  // light grid) or read back.
  const VkBuffer depth = seeds_a_.handle(), dist = distance_.handle();
  range("grown.images");
  add(27.0f * fv + 4.0f * fv, [=, this](VkCommandBuffer cmd) {
    field_.set_layout(VK_IMAGE_LAYOUT_UNDEFINED);
    modeling_.set_layout(VK_IMAGE_LAYOUT_UNDEFINED);
    field_.cmd_transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
    modeling_.cmd_transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
    pass(cmd, *pipes_.store_field, {dist}, vg);
    pass(cmd, *pipes_.store_modeling, {dist, depth, attributes}, vg);
    field_.cmd_transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    modeling_.cmd_transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  });
  return list;
}

std::vector<GrownUpdateChunk> GpuGrownAsset::update_chunks(const GpuCloudSolver& solver, int frames) const {
  const std::vector<Stage>& list = stages(solver, GrownUpdateOrder::Interleaved);
  const int n = int(list.size());
  frames = std::clamp(frames, 1, n);
  std::vector<GrownUpdateChunk> chunks;
  if (frames == 1) return {{0, n}};
  // The last stage (the images) has a frame of its own: that frame also rebuilds the light grid. The stages before
  // it are cut into frames - 1 runs of about equal estimated cost.
  float total = 0.0f;
  for (int i = 0; i + 1 < n; ++i) total += list[size_t(i)].cost;
  const int runs = frames - 1;
  int first = 0;
  float done = 0.0f;
  for (int k = 1; k <= runs; ++k) {
    const float goal = total * float(k) / float(runs);
    int last = first;
    // At least one stage a run, and leave one for each run still to come.
    while (last < n - 1 - (runs - k) && (last == first || done + list[size_t(last)].cost * 0.5f <= goal))
      done += list[size_t(last++)].cost;
    if (k == runs) {
      while (last < n - 1) done += list[size_t(last++)].cost;
    }
    if (last > first) chunks.push_back({first, last - first});
    first = last;
  }
  chunks.push_back({n - 1, 1});
  return chunks;
}

void GpuGrownAsset::record_update(VkCommandBuffer cmd, const GpuCloudSolver& solver, gpu::GpuTimer* timer,
                                  GrownUpdateOrder order) {
  record_update_stages(cmd, solver, 0, INT32_MAX, timer, order);
}

void GpuGrownAsset::record_update_stages(VkCommandBuffer cmd, const GpuCloudSolver& solver, int first, int count,
                                         gpu::GpuTimer* timer, GrownUpdateOrder order) {
  const std::vector<Stage>& list = stages(solver, order);
  const int n = int(list.size());
  if (first < 0 || first >= n || count < 1)
    fail("grow_gpu: update stages [%d, +%d) outside the update's %d", first, count, n);
  const int last = int(std::min<int64_t>(int64_t(first) + count, n));
  gpu::ScopedLabel label(ctx_, cmd, "grown_asset.update");
  uint32_t open = UINT32_MAX;
  // A run that does not start the update follows the run before it, recorded in an earlier frame: the barrier that
  // ended that run orders it, and this one orders it again within this command buffer's scope.
  if (first > 0) grow_barrier(cmd);
  for (int i = first; i < last; ++i) {
    const Stage& s = list[size_t(i)];
    if (timer && s.range) {
      if (open != UINT32_MAX) timer->end(cmd, open);
      open = timer->begin(cmd, s.range);
    }
    for (const auto& p : s.passes) p(cmd);
    if (i + 1 < n) grow_barrier(cmd);
  }
  if (timer && open != UINT32_MAX) timer->end(cmd, open);
  stages_recorded_ += last - first;
  if (last == n) ++updates_;
}

void GpuGrownAsset::record_modeling_copy(VkCommandBuffer cmd, VkBuffer dst) const {
  modeling_.cmd_transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  VkBufferImageCopy r{};
  r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  r.imageExtent = modeling_.extent();
  vkCmdCopyImageToBuffer(cmd, modeling_.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, 1, &r);
  modeling_.cmd_transition(cmd, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  gpu::cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

std::vector<uint8_t> GpuGrownAsset::read_modeling() const { return gpu::read_image_bytes(ctx_, modeling_); }

std::vector<uint16_t> GpuGrownAsset::read_field() const {
  const std::vector<uint8_t> bytes = gpu::read_image_bytes(ctx_, field_);
  std::vector<uint16_t> out(bytes.size() / 2);
  std::memcpy(out.data(), bytes.data(), out.size() * 2);
  return out;
}

std::vector<float> GpuGrownAsset::read_cloud_water() const {
  std::vector<float> out(grid_.count());
  fine_.download(out.data(), out.size() * sizeof(float));
  return out;
}

std::vector<float> GpuGrownAsset::read_distance() const {
  std::vector<float> out(grid_.count());
  distance_.download(out.data(), out.size() * sizeof(float));
  return out;
}

std::array<float, GROWN_QUANTITIES> GpuGrownAsset::read_percentiles() const {
  uint32_t state[GROWN_SELECT_HEADER];
  select_.download(state, sizeof state);
  std::array<float, GROWN_QUANTITIES> out{};
  for (int q = 0; q < GROWN_QUANTITIES; ++q) {
    const uint32_t* s = state + q * GROWN_SELECT_STRIDE;
    float v = 0.0f;
    if (s[GROWN_SELECT_COUNT] > 0) std::memcpy(&v, &s[GROWN_SELECT_PREFIX], sizeof v);
    out[size_t(q)] = v;
  }
  return out;
}

}  // namespace cumulo::clouds::grow_gpu
