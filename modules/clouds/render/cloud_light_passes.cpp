// Steps 0, 1 and 1b of the cloud frame (cloud_passes.h): the assets imported, the light grid, the shadow map.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/context.h"
#include "modules/clouds/render/cloud_passes.h"

namespace cumulo::clouds::render {
namespace {

uint64_t instance_key(const CloudInstance& inst, const CloudResourcesDesc& d) {
  struct Key {
    const void* asset;
    float v[12];
    uint32_t grid[3];
  } k{};
  k.asset = inst.asset.get();
  const glm::quat q = glm::normalize(inst.rotation);
  // The weather's density, dissipation and coverage are not in it: a turning weather changes them every frame, and
  // the sweep follows small changes level by level like a sun moving less than the rebuild threshold (below).
  const float vals[12] = {inst.position.x, inst.position.y, inst.position.z, q.x, q.y, q.z, q.w, inst.scale,
                          0.0f, 0.0f, 0.0f, 0.0f};
  std::memcpy(k.v, vals, sizeof vals);
  k.grid[0] = d.light_grid_size.x, k.grid[1] = d.light_grid_size.y, k.grid[2] = d.light_grid_size.z;
  return hash64(&k, sizeof k);
}

// The asset textures a light pass samples, captured by value into its record callback: declared as reads, and
// bound for one asset slot (push descriptors: rebound when an instance reads another asset).
struct AssetTextures {
  std::vector<TextureHandle> modelings, fields, coverages;
  TextureHandle noise;
  explicit AssetTextures(const CloudLightOutputs& a)
      : modelings(a.modelings), fields(a.fields), coverages(a.coverages), noise(a.noise) {}
  void read(PassBuilder& b) const {
    for (size_t a = 0; a < modelings.size(); ++a) {
      b.read(modelings[a], Usage::Sampled);
      b.read(fields[a], Usage::Sampled);
    }
    for (TextureHandle t : coverages) b.read(t, Usage::Sampled);
    b.read(noise, Usage::Sampled);
  }
  void bind(Bindings& bindings, PassContext& c, const CloudResources& r, uint32_t a) const {
    bindings.sampled(CLOUD_BINDING_MODELING, c.view(modelings[a]), r.linear_clamp, c.layout(modelings[a]))
        .sampled(CLOUD_BINDING_FIELD, c.view(fields[a]), r.linear_clamp, c.layout(fields[a]))
        .sampled(CLOUD_BINDING_NOISE, c.view(noise), r.linear_repeat, c.layout(noise));
    if (!coverages.empty())
      bindings.sampled(CLOUD_BINDING_COVERAGE, c.view(coverages[a]), r.linear_clamp, c.layout(coverages[a]));
  }
};

// A persistent image the light grid's size and format (what is derived from the grid: its local terms, the solved
// field), made anew when the grid's size changed; true when it was (its content is undefined).
bool match_grid_image(gpu::Context& ctx, VkExtent3D ge, const char* name, gpu::Image& image,
                      cumulo::render::PersistentTexture& texture) {
  if (image && image.extent().width == ge.width && image.extent().height == ge.height && image.extent().depth == ge.depth)
    return false;
  if (image) ctx.wait_idle();  // frames in flight may still sample the old image (rare: the grid changed size)
  image = gpu::Image(ctx, gpu::ImageDesc::tex3d(ge.width, ge.height, ge.depth, kGridFormat,
                                                VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1, name));
  texture = {name, TextureDesc::absolute(kGridFormat, ge.width, ge.height, ge.depth), image.handle(), image.view(),
             ResourceState::undefined()};
  return true;
}

}  // namespace

CloudLightOutputs import_cloud_assets(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in) {
  if (in.instances.size() > kMaxInstances)
    fail("clouds: %zu cloudscape instances, at most %u per frame", in.instances.size(), kMaxInstances);
  if (in.lights.size() > kMaxPointLights)
    fail("clouds: %zu point lights, at most %u per frame", in.lights.size(), kMaxPointLights);
  // Distinct assets in order of first use: slot 0 and, for a second asset, slot 1 (the march binds both).
  std::vector<const CloudAsset*> assets;
  CloudLightOutputs out;
  for (const CloudInstance& inst : in.instances) {
    if (!inst.asset) fail("clouds: a cloudscape instance has no asset");
    auto it = std::find(assets.begin(), assets.end(), inst.asset.get());
    if (it == assets.end()) {
      if (assets.size() == kMaxAssets)
        fail("clouds: more than %u cloudscape assets in one frame (%s, %s, %s): instances may share an asset", kMaxAssets,
             assets[0]->folder.string().c_str(), assets[1]->folder.string().c_str(), inst.asset->folder.string().c_str());
      assets.push_back(inst.asset.get());
      it = assets.end() - 1;
    }
    out.slots.push_back(uint32_t(it - assets.begin()));
  }
  for (const CloudAsset* a : assets)
    if (a->formats != assets[0]->formats)
      fail("clouds: the cloudscape assets %s and %s use different formats in one frame", assets[0]->folder.string().c_str(),
           a->folder.string().c_str());
  out.asset_slots = int(assets.size());
  out.bc1 = assets[0]->formats.bc1_field;
  // The BC1 modeling NVDF has no alpha: its coverage thresholds come from the asset's coverage texture.
  out.coverage_texture = assets[0]->formats.bc1_modeling;
  auto import_3d = [&](const std::string& name, const gpu::Image& img) {
    const VkExtent3D e = img.extent();
    TextureDesc d = TextureDesc::absolute(img.format(), e.width, e.height, e.depth);
    d.type = cumulo::render::ImageType::Image3D;
    d.mips = img.mips();
    return graph.import_texture(name, d, img.handle(), img.view(), sampled_state());
  };
  for (size_t a = 0; a < assets.size(); ++a) {
    const std::string suffix = a ? "." + std::to_string(a) : "";
    out.modelings.push_back(import_3d("clouds.modeling" + suffix, assets[a]->modeling_image()));
    out.fields.push_back(import_3d("clouds.field" + suffix, assets[a]->field_image()));
    out.fairs.push_back(import_3d("clouds.field_fair" + suffix, assets[a]->field_fair_image()));
    if (out.coverage_texture) out.coverages.push_back(import_3d("clouds.coverage" + suffix, assets[a]->coverage));
  }
  out.noise = import_3d("clouds.noise", res.noise->image);
  return out;
}

LightGridWork plan_light_grids(CloudResources& res, const CloudFrameInputs& in) {
  gpu::Context& ctx = res.ctx;
  const CloudSettings& s = in.settings;
  const uint32_t n = uint32_t(in.instances.size());
  const glm::uvec3 gs = res.desc.light_grid_size;
  LightGridWork work;
  work.grids.resize(n);
  work.plans.resize(n);
  if (!res.grid_image || res.grid_instances != n || res.grid_image.extent().width != gs.x ||
      res.grid_image.extent().height != gs.y || res.grid_image.extent().depth != gs.z * n) {
    if (res.grid_image) ctx.wait_idle();  // frames in flight may still sample the old grid (rare: instance count changes)
    res.grid_image = gpu::Image(ctx, gpu::ImageDesc::tex3d(gs.x, gs.y, gs.z * n, kGridFormat,
                                                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1,
                                                           "clouds.light_grid"));
    res.grid_texture = {"clouds.light_grid", TextureDesc::absolute(kGridFormat, gs.x, gs.y, gs.z * n),
                        res.grid_image.handle(), res.grid_image.view(), ResourceState::undefined()};
    res.grid_instances = n;
    for (auto& g : res.grids) g = {};
  }
  const float cos_threshold = std::cos(glm::radians(s.sun_rebuild_degrees));
  const glm::vec3 sun_world = glm::normalize(in.sun_direction);
  const bool sweep = s.light_grid_method == CloudLightGridMethod::Sweep;
  for (uint32_t i = 0; i < n; ++i) {
    CloudResources::LightGrid& g = res.grids[i];
    LightGridWork::Grid& w = work.grids[i];
    const CloudInstance& inst = in.instances[i];
    const glm::vec3 sun_asset = glm::normalize(glm::inverse(glm::normalize(inst.rotation)) * sun_world);
    const uint64_t key = instance_key(inst, res.desc);
    // A weather change of more than 10 % of what the grid was built with rebuilds it; a smaller one is swept in (before,
    // every frame of a turning weather rebuilt the whole grid: `cumulo soak` measured 80 ms a frame on lavapipe).
    const glm::vec3 weather(inst.density, inst.dissipation, inst.coverage);
    const glm::vec3 weather_change = glm::abs(weather - g.weather);
    const bool weather_far = glm::any(glm::greaterThan(weather_change, 0.1f * glm::max(glm::abs(g.weather), glm::vec3(0.05f))));
    const bool rebuild = !g.valid || in.rebuild_light_grid || inst.asset_changed || key != g.key ||
                         glm::dot(sun_asset, g.sun) < cos_threshold || weather_far;
    const uint32_t slab = gs.z / res.desc.light_grid_divisions;
    // The sweep amortizes by levels over the whole grid (light_grid_sweep.comp says why).
    const uint32_t levels_per_frame = (gs.y + res.desc.light_grid_divisions - 1) / res.desc.light_grid_divisions;
    // The sweep reads the noise by its mean, so the wind does not move it: with the sun still for a
    // whole cycle of levels the grid is current and the frame's update would rewrite the same values.
    // (The rays method samples the scrolling noise and keeps updating.)
    g.frames_same_sun = sun_asset == g.last_sun && weather == g.last_weather ? g.frames_same_sun + 1 : 0;
    g.last_sun = sun_asset;
    g.last_weather = weather;
    const uint32_t divisions = res.desc.light_grid_divisions;
    if (inst.asset_grew && sweep && !rebuild) {
      // The new images swept in. A cycle that starts at the first level (the one nearest the light) makes the grid
      // current: each level reads a level above it already swept over the new images. With no cycle under way one
      // starts now; else the one under way finishes and one more whole cycle follows (restarting it instead would
      // starve its last levels when the images change faster than a cycle).
      const bool under_way = g.sweep_left > 0 || g.frames_same_sun < divisions;
      if (!under_way) {
        g.sweep_phase = uint32_t(in.frame_index % divisions);
        g.sweep_left = divisions;
      } else {
        const uint32_t at = uint32_t((in.frame_index + divisions - g.sweep_phase) % divisions);
        g.sweep_left = divisions - at + divisions;
      }
    }
    const bool current =
        sweep && !s.light_grid_always_update && g.frames_same_sun >= divisions && g.sweep_left == 0;
    if (rebuild) {
      w.first = 0, w.layers = gs.z;
      w.level_first = 0, w.level_count = gs.y;
      g.sun = sun_asset, g.key = key, g.valid = true, g.weather = weather;
      g.frames_same_sun = res.desc.light_grid_divisions;  // every level computed with this sun
      g.sweep_left = 0;
      ++res.rebuilds;
      work.rebuilt = true;
    } else if (current) {
      w.first = 0, w.layers = 0;
      w.level_first = 0, w.level_count = 0;
    } else if (sweep) {
      w.first = 0, w.layers = gs.z;
      const uint32_t at = uint32_t((in.frame_index + divisions - g.sweep_phase) % divisions);
      w.level_first = std::min(gs.y, at * levels_per_frame);
      if (g.sweep_left > 0) --g.sweep_left;
      w.level_count = std::min(levels_per_frame, gs.y - w.level_first);
    } else {
      w.first = uint32_t(in.frame_index % res.desc.light_grid_divisions) * slab;
      w.layers = slab;
    }
    const glm::mat3 to_asset = glm::mat3(glm::inverse(glm::normalize(inst.rotation)));
    const bool sun_up = (to_asset * sun_world).y >= 0.0f, sky_up = (to_asset * glm::vec3(0, 1, 0)).y >= 0.0f;
    if (sun_up == sky_up) work.plans[i] = {{3, 4, 0}, {sun_up, !sun_up, sun_up}};
    else work.plans[i] = {{1, 2, 4}, {sun_up, sky_up, !sun_up}};
    work.any |= w.layers > 0 && (!sweep || w.level_count > 0);
  }
  return work;
}

TextureHandle add_light_grid_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                  const LightGridWork& work, const CloudLightOutputs& assets, TextureHandle grid,
                                  VkBuffer ubo_handle) {
  if (!work.any) return grid;
  const CloudSettings& s = in.settings;
  const bool sweep = s.light_grid_method == CloudLightGridMethod::Sweep;
  gpu::Pipeline* grid_pipe = sweep ? &res.sweep(assets.bc1, assets.coverage_texture) : &res.grid(assets.bc1, assets.coverage_texture);
  const CloudResourcesDesc rdesc = res.desc;
  CloudResources* r = &res;
  const std::vector<LightGridWork::Grid>& grids = work.grids;
  const std::vector<LightGridWork::SweepPlan>& plans = work.plans;
  const std::vector<uint32_t>& slots = assets.slots;
  const AssetTextures textures(assets);
  graph.add_pass("clouds.light_grid", Queue::Compute,
      [&](PassBuilder& b) {
        textures.read(b);
        grid = b.read_write(grid, Usage::StorageWrite);
      },
      [r, grid_pipe, grids, plans, sweep, grid, textures, slots, ubo_handle, rdesc](PassContext& c) {
        const VkExtent3D e = c.extent(grid);
        // Each instance's dispatches read its own asset (push descriptors: rebound when the asset changes).
        uint32_t bound = UINT32_MAX;
        auto bind = [&](uint32_t a) {
          if (a == bound) return;
          bound = a;
          Bindings bindings(*grid_pipe);
          bindings.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize).storage(CLOUD_BINDING_GRID_OUT, c.view(grid));
          textures.bind(bindings, c, *r, a);
          bindings.push(r->ctx, c.cmd());
        };
        for (uint32_t i = 0; i < grids.size(); ++i) {
          if (grids[i].layers == 0 || (sweep && grids[i].level_count == 0)) continue;
          bind(slots[i]);
          shared::CloudLightGridPush pc{};
          if (!sweep) {
            pc.region = glm::uvec4(i, grids[i].first, grids[i].layers, 0);
            pc.grid = glm::vec4(float(rdesc.light_grid_sun_steps), float(rdesc.light_grid_sky_steps),
                                float(rdesc.light_grid_size.z), 0.0f);
            grid_pipe->push_constants(c.cmd(), pc);
            grid_pipe->dispatch_threads(c.cmd(), e.width, e.height, grids[i].layers);
            continue;
          }
          // One dispatch per level; each level reads the one before it (written by the previous
          // dispatch of this pass): the only barriers recorded inside a cloud pass.
          for (uint32_t sweep_index = 0; sweep_index < 3 && plans[i].channels[sweep_index]; ++sweep_index)
            for (uint32_t k = grids[i].level_first; k < grids[i].level_first + grids[i].level_count; ++k) {
              const uint32_t level = plans[i].down[sweep_index] ? e.height - 1 - k : k;
              if (k > grids[i].level_first || sweep_index > 0 || i > 0)
                gpu::cmd_memory_barrier(c.cmd(), VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
              pc.region = glm::uvec4(i, grids[i].first, grids[i].layers, level);
              pc.grid = glm::vec4(float(rdesc.light_grid_sweep_samples), float(plans[i].channels[sweep_index]),
                                  float(rdesc.light_grid_size.z), 0.0f);
              grid_pipe->push_constants(c.cmd(), pc);
              grid_pipe->dispatch_threads(c.cmd(), e.width, 1, grids[i].layers);
            }
        }
      });
  return grid;
}

TextureHandle add_light_local_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                   const LightGridWork& work, TextureHandle grid, VkBuffer ubo_handle) {
  gpu::Context& ctx = res.ctx;
  const VkExtent3D ge = res.grid_image.extent();
  if (match_grid_image(ctx, ge, "clouds.light_grid_local", res.local_image, res.local_texture)) res.local_valid = false;
  TextureHandle local = graph.import_persistent(res.local_texture);
  const bool shadows = in.settings.instance_shadows;
  // A rebuilt grid (an instance moved, the sun turned) changes the other instances' shadow everywhere; a partial
  // update changes its levels (sweep) or layers (rays), and the other instances' values read from them follow when
  // their own levels come round, within one cycle of the grid's updates.
  const bool whole = !res.local_valid || work.rebuilt || shadows != res.local_shadows;
  if (!whole && !work.any) return local;
  const uint32_t n = uint32_t(in.instances.size());
  const uint32_t layers = res.desc.light_grid_size.z, levels = ge.height;
  const bool sweep = in.settings.light_grid_method == CloudLightGridMethod::Sweep;
  // Per instance and dispatch: the instance, first level, level count, first z layer, layer count. A partial sweep
  // updated its levels in sweep order, from the top (the grid's levels H-1-k) for some channels and from the bottom
  // (k) for others: both ranges.
  std::vector<std::pair<uint32_t, glm::uvec4>> regions;
  for (uint32_t i = 0; i < n && i < work.grids.size(); ++i) {
    const LightGridWork::Grid& g = work.grids[i];
    if (whole) {
      regions.push_back({i, {0u, levels, 0u, layers}});
    } else if (g.layers > 0 && !sweep) {
      regions.push_back({i, {0u, levels, g.first, g.layers}});
    } else if (g.layers > 0 && g.level_count > 0) {
      const uint32_t first = std::min(g.level_first, levels), count = std::min(g.level_count, levels - first);
      const uint32_t mirrored = levels - first - count;
      if (mirrored >= first + count || mirrored + count <= first) {
        regions.push_back({i, {first, count, g.first, g.layers}});
        regions.push_back({i, {mirrored, count, g.first, g.layers}});
      } else {  // overlapping: their union
        const uint32_t lo = std::min(first, mirrored), hi = std::max(first, mirrored) + count;
        regions.push_back({i, {lo, hi - lo, g.first, g.layers}});
      }
    }
  }
  res.local_valid = true;
  res.local_shadows = shadows;
  gpu::Pipeline* pipe = res.local_pipe;
  CloudResources* r = &res;
  graph.add_pass("clouds.light_grid_local", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(grid, Usage::Sampled);
        local = b.read_write(local, Usage::StorageWrite);
        b.side_effect();  // kept for the frames that reuse it
      },
      [r, pipe, grid, local, ubo_handle, regions, layers](PassContext& c) {
        Bindings(*pipe)
            .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
            .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
            .storage(CLOUD_BINDING_LOCAL_OUT, c.view(local))
            .push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(local);
        for (const auto& [i, region] : regions) {
          if (region.y == 0 || region.w == 0) continue;
          shared::CloudLightGridPush pc{};
          pc.region = glm::uvec4(i, region.x, region.y, region.z);
          pc.grid = glm::vec4(0.0f, 0.0f, float(layers), float(region.w));
          pipe->push_constants(c.cmd(), pc);
          // One work group in z (light_grid_local.comp): levels x layers along y.
          pipe->dispatch_threads(c.cmd(), e.width, region.y * region.w, 1);
        }
      });
  return local;
}

TextureHandle add_ms_solve_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                const LightGridWork& work, const CloudLightOutputs& assets, VkBuffer ubo_handle) {
  const CloudSettings& s = in.settings;
  if (!s.ms_solve) return {};
  gpu::Context& ctx = res.ctx;
  const VkExtent3D ge = res.grid_image.extent();
  if (ge.height > kMaxSolveLevels)
    fail("clouds: the solve lighting (--cloud-lighting solve) takes a light grid of at most %u levels; this one has %u",
         kMaxSolveLevels, ge.height);
  if (match_grid_image(ctx, ge, "clouds.ms_field", res.ms_image, res.ms_texture)) res.ms_valid = false;
  TextureHandle ms = graph.import_persistent(res.ms_texture);
  // A new image's fluence starts at zero (its first setup writes it; later ones warm-start from the last solution).
  const bool fresh = !res.ms_valid;
  // Rounds over the grid's tiles: a new image or a rebuild after a long rest, the whole solve; a rebuild soon after
  // the last solve (the weather's coverage changing, a sun crossing the rebuild threshold again) starts from that
  // solution and takes one round; a partial update (the sun moved less than CloudSettings::sun_rebuild_degrees)
  // ms_solve_update_iterations (0 by default: the field lags the sun by less than a degree until the next rebuild).
  const bool recent = res.ms_valid && in.frame_index < res.ms_frame + 2ull * res.desc.light_grid_divisions;
  const uint32_t rounds = fresh ? s.ms_solve_iterations
                          : work.rebuilt ? (recent ? std::min(1u, s.ms_solve_iterations) : s.ms_solve_iterations)
                          : work.any     ? s.ms_solve_update_iterations
                                         : 0;
  if (rounds == 0 && !fresh) return ms;
  const uint32_t local = s.ms_solve_local_iterations;
  res.ms_valid = true;
  res.ms_frame = in.frame_index;
  gpu::Pipeline* pipe = &res.ms_solve(assets.bc1, assets.coverage_texture);
  CloudResources* r = &res;
  const TextureHandle grid = assets.grid;
  const std::vector<uint32_t>& slots = assets.slots;
  const AssetTextures textures(assets);
  const uint32_t n = uint32_t(in.instances.size());
  const uint32_t layers = res.desc.light_grid_size.z;
  const float omega = s.ms_solve_omega;
  graph.add_pass("clouds.ms_solve", Queue::Compute,
      [&](PassBuilder& b) {
        textures.read(b);
        b.read(grid, Usage::Sampled);
        ms = b.read_write(ms, Usage::StorageWrite);
        b.side_effect();  // kept for the frames that reuse it
      },
      [r, pipe, grid, ms, textures, slots, ubo_handle, n, layers, rounds, local, omega, fresh](PassContext& c) {
        const VkExtent3D e = c.extent(ms);
        bool first = true;
        uint32_t bound = UINT32_MAX;
        for (uint32_t i = 0; i < n; ++i) {
          if (slots[i] != bound) {
            bound = slots[i];
            Bindings bindings(*pipe);
            bindings.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
                .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
                .storage(CLOUD_BINDING_MS_OUT, c.view(ms));
            textures.bind(bindings, c, *r, bound);
            bindings.push(r->ctx, c.cmd());
          }
          shared::CloudLightGridPush pc{};
          pc.grid = glm::vec4(omega, float(local), 0.0f, 0.0f);
          // Setup (mode 0; w = 1: a new image, whose fluence starts at zero), the tiles of each colour in turn
          // (modes 1, 2), then the open air's values for the march's filtering (mode 3).
          std::vector<uint32_t> modes{0u};
          for (uint32_t k = 0; k < rounds; ++k) modes.insert(modes.end(), {1u, 2u});
          modes.push_back(3u);
          for (uint32_t mode : modes) {
            // Each step reads what the one before wrote (the only barriers inside this pass).
            if (!first)
              gpu::cmd_memory_barrier(c.cmd(), VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
            first = false;
            pc.region = glm::uvec4(i, mode, layers, fresh ? 1u : 0u);
            pipe->push_constants(c.cmd(), pc);
            pipe->dispatch_threads(c.cmd(), e.width, layers, 1);
          }
        }
      });
  return ms;
}

void add_shadow_map_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, bool grid_changed,
                         VkBuffer ubo_handle, CloudLightOutputs& out) {
  // A persistent texture, recomputed only when the light grid changed this frame or the plane moved
  // (the map is the grid's sums at the boxes' entries: nothing else changes it).
  const std::optional<cumulo::render::LightShadowMap> plane = shadow_plane(in, res.desc.shadow_map_size);
  if (!plane) return;
  const uint32_t sm = res.desc.shadow_map_size;
  if (!res.shadow_image) {
    res.shadow_image = gpu::Image(res.ctx, gpu::ImageDesc::tex2d(sm, sm, VK_FORMAT_R16_SFLOAT,
                                                                 VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1,
                                                                 "clouds.shadow_map"));
    res.shadow_texture = {"clouds.shadow_map", TextureDesc::absolute(VK_FORMAT_R16_SFLOAT, sm, sm),
                          res.shadow_image.handle(), res.shadow_image.view(), ResourceState::undefined()};
  }
  TextureHandle shadow = graph.import_persistent(res.shadow_texture);
  const TextureHandle grid = out.grid;
  const glm::vec3 sun_world = glm::normalize(in.sun_direction);
  const glm::vec4 key(plane->origin, plane->size.x, plane->height);
  const bool stale = grid_changed || !res.shadow_valid || key != res.shadow_key || sun_world != res.shadow_sun;
  if (stale) {
    gpu::Pipeline* pipe = res.shadow_pipe;
    CloudResources* r = &res;
    shared::CloudShadowPush pc{};
    pc.plane = glm::vec4(plane->origin, plane->size);
    pc.light = glm::vec4(sun_world, plane->height);
    graph.add_pass("clouds.shadow_map", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(grid, Usage::Sampled);
          shadow = b.write(shadow, Usage::StorageWrite);
          b.side_effect();  // kept for the frames that reuse it
        },
        [r, pipe, grid, shadow, ubo_handle, pc](PassContext& c) {
          Bindings(*pipe)
              .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
              .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
              .storage(CLOUD_BINDING_SHADOW_OUT, c.view(shadow))
              .push(r->ctx, c.cmd());
          pipe->push_constants(c.cmd(), pc);
          const VkExtent3D e = c.extent(shadow);
          pipe->dispatch_threads(c.cmd(), e.width, e.height);
        });
    res.shadow_key = key;
    res.shadow_sun = sun_world;
    res.shadow_valid = true;
    ++res.shadow_updates;
  }
  out.shadow = *plane;
  out.shadow.texture = shadow;
  out.shadow.version = res.shadow_updates;  // >= 1: recomputed above at least once
}

}  // namespace cumulo::clouds::render
