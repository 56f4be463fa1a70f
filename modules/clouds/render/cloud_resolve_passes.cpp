// Steps 3 and 4 of the cloud frame (cloud_passes.h): temporal accumulation and the composite over the scene.
#include "engine/gpu/context.h"
#include "modules/clouds/render/cloud_passes.h"

namespace cumulo::clouds::render {

TextureHandle add_temporal_pass(CloudResources& res, RenderGraph& graph, const MarchOutputs& march,
                                const HistoryImports& history, VkBuffer ubo_handle) {
  gpu::Pipeline* pipe = res.temporal_pipe;
  CloudResources* r = &res;
  const TextureHandle color = march.color, cdepth = march.depth, prev = history.prev;
  TextureHandle next = history.next;
  graph.add_pass("clouds.temporal", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(color, Usage::Sampled);
        b.read(cdepth, Usage::Sampled);
        b.read(prev, Usage::Sampled);
        next = b.write(next, Usage::StorageWrite);
      },
      [r, pipe, color, cdepth, prev, next, ubo_handle](PassContext& c) {
        Bindings(*pipe)
            .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
            .sampled(CLOUD_BINDING_CURRENT, c.view(color), r->nearest_clamp, c.layout(color))
            .sampled(CLOUD_BINDING_CURRENT_DEPTH, c.view(cdepth), r->nearest_clamp, c.layout(cdepth))
            .sampled(CLOUD_BINDING_HISTORY, c.view(prev), r->linear_clamp, c.layout(prev))
            .storage(CLOUD_BINDING_ACCUM_OUT, c.view(next))
            .push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(next);
        pipe->push_constants(c.cmd(), target_push(e));
        pipe->dispatch_threads(c.cmd(), e.width, e.height);
      });
  return next;
}

TextureHandle add_composite_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                 const CloudLightOutputs& light, TextureHandle final_color, TextureHandle cdepth,
                                 TextureHandle depth, TextureHandle hdr, VkBuffer ubo_handle) {
  const bool sky = in.sky_color.valid() && in.sky_depth.valid();
  const bool aerial = in.aerial.valid();
  // Clouds below the output's size (dynamic resolution): upsampled depth-aware against the scene's depth.
  const VkExtent2D out = graph.output_size(), clouds = march_extent(graph, in);
  const bool upsample = clouds.width != out.width || clouds.height != out.height;
  int envelope = !(in.envelope_color.valid() && in.envelope_depth.valid()) ? 0
                 : in.envelope_near_color.valid() && in.envelope_near_depth.valid() ? 2 : 1;
  if (envelope == 1 && in.envelope_upsample) envelope = 3;
  const bool scene_depth = sky || upsample || envelope > 0;
  const CloudDebugView view = in.settings.debug;
  gpu::Pipeline* comp =
      &res.composite(sky, aerial, upsample, view == CloudDebugView::Steps || view == CloudDebugView::LightGrid, envelope);
  CloudResources* r = &res;
  const TextureHandle grid = light.grid;
  const TextureHandle sky_color = in.sky_color, sky_depth = in.sky_depth, aerial_tex = in.aerial;
  const TextureHandle env_c = in.envelope_color, env_d = in.envelope_depth, env_nc = in.envelope_near_color,
                      env_nd = in.envelope_near_depth;
  graph.add_pass("clouds.composite", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(final_color, Usage::Sampled);
        b.read(cdepth, Usage::Sampled);
        b.read(grid, Usage::Sampled);
        if (sky) {
          b.read(sky_color, Usage::Sampled);
          b.read(sky_depth, Usage::Sampled);
        }
        if (scene_depth) b.read(depth, Usage::Sampled);
        if (aerial) b.read(aerial_tex, Usage::Sampled);
        if (envelope > 0) {
          b.read(env_c, Usage::Sampled);
          b.read(env_d, Usage::Sampled);
        }
        if (envelope == 2) {
          b.read(env_nc, Usage::Sampled);
          b.read(env_nd, Usage::Sampled);
        }
        hdr = b.read_write(hdr, Usage::StorageWrite);
      },
      [r, comp, final_color, cdepth, grid, hdr, ubo_handle, sky, sky_color, sky_depth, depth, scene_depth, aerial,
       aerial_tex, envelope, env_c, env_d, env_nc, env_nd](PassContext& c) {
        Bindings bind(*comp);
        bind.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
            .sampled(CLOUD_BINDING_CLOUDS, c.view(final_color), r->nearest_clamp, c.layout(final_color))
            .sampled(CLOUD_BINDING_CLOUD_DEPTH, c.view(cdepth), r->nearest_clamp, c.layout(cdepth))
            .sampled(CLOUD_BINDING_DEBUG_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
            .storage(CLOUD_BINDING_HDR, c.view(hdr));
        if (sky)
          bind.sampled(CLOUD_BINDING_SKY_COLOR, c.view(sky_color), r->linear_clamp, c.layout(sky_color))
              .sampled(CLOUD_BINDING_SKY_DEPTH, c.view(sky_depth), r->nearest_clamp, c.layout(sky_depth));
        if (scene_depth)
          bind.sampled(CLOUD_BINDING_SCENE_DEPTH_COMPOSITE, c.view(depth), r->nearest_clamp, c.layout(depth));
        if (aerial) bind.sampled(CLOUD_BINDING_AERIAL, c.view(aerial_tex), r->linear_clamp, c.layout(aerial_tex));
        if (envelope > 0)
          bind.sampled(CLOUD_BINDING_ENVELOPE_COLOR, c.view(env_c), r->linear_clamp, c.layout(env_c))
              .sampled(CLOUD_BINDING_ENVELOPE_DEPTH, c.view(env_d), r->nearest_clamp, c.layout(env_d));
        if (envelope == 2)
          bind.sampled(CLOUD_BINDING_ENVELOPE_NEAR_COLOR, c.view(env_nc), r->nearest_clamp, c.layout(env_nc))
              .sampled(CLOUD_BINDING_ENVELOPE_NEAR_DEPTH, c.view(env_nd), r->nearest_clamp, c.layout(env_nd));
        bind.push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(hdr);
        comp->push_constants(c.cmd(), target_push(e));
        comp->dispatch_threads(c.cmd(), e.width, e.height);
      });
  return hdr;
}

}  // namespace cumulo::clouds::render
