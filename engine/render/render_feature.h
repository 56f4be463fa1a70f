#pragma once
// How a module's rendering enters the frame without the engine knowing it (DESIGN.md "Modules"; Granite's
// RenderPassCreator). A RenderFeature creates its GPU objects once, with the context and the renderer's
// pipeline library (so its shaders hot-reload with the engine's), and adds render-graph passes at named
// stages of every frame:
//
//   Stage::BeforeScene   before geometry: hdr and depth exist but hold nothing yet (compute that later
//                        passes read: light grids, LUTs, simulation textures)
//   Stage::AfterOpaque   after geometry and sky: hdr (scene colour) and depth are complete; a pass may
//                        write a new version of hdr (clouds, fog, transparent effects)
//   Stage::AfterTonemap  after tonemap: `output` is the display-referred target (UI, debug overlays)
//
//   struct Fog : render::RenderFeature {
//     gpu::Pipeline* pipe = nullptr;
//     void create_gpu(render::GpuServices& g) override { pipe = &g.library.compute({"fog/fog_apply.comp"}); }
//     void add_passes(render::Stage stage, render::StageContext& f) override {
//       if (stage != render::Stage::AfterOpaque) return;
//       auto u = f.uniforms.push(make_params(f.snapshot));
//       f.graph.add_pass("fog", render::Queue::Compute,
//           [&](render::PassBuilder& b) { b.read(f.depth, render::Usage::Sampled); f.hdr = b.read_write(f.hdr, render::Usage::StorageWrite); },
//           [this, u, hdr = f.hdr, depth = f.depth](render::PassContext& c) { ... });
//     }
//   };
#include <cstdint>

#include "engine/render/frame_snapshot.h"
#include "engine/render/graph/render_graph.h"
#include "engine/render/light_depth.h"
#include "engine/render/stage_resources.h"
#include "engine/render/uniform_allocator.h"

namespace cumulo::gpu {
class Context;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::render {

enum class Stage : uint8_t { BeforeScene, AfterOpaque, AfterTonemap };
inline constexpr int kStageCount = 3;
const char* stage_name(Stage stage);

// What a feature gets to create its GPU objects with. Objects it creates live until destroy_gpu().
struct GpuServices {
  gpu::Context& ctx;
  gpu::PipelineLibrary& library;  // shared with the engine's passes: poll_reload() covers module shaders
};

// One stage of one frame. Handles are the current versions; a pass that writes hdr (or output) stores
// the new version back here so the next pass and the engine see it.
// The key light's transmittance over the scene (cloud shadows), a texture a feature writes at
// Stage::BeforeScene for the geometry pass: R16F (any float format), texel (u, v) = transmittance
// along the light's ray through the point (origin.x + u * size.x, height, origin.y + v * size.y) of a
// horizontal plane below what casts the shadow; the geometry projects each point onto that plane along
// the light (outside the map: no shadow). Exact below the plane; above it, a point gets the shadow of
// the whole column it projects onto.
struct LightShadowMap {
  TextureHandle texture;        // invalid: no map this frame
  glm::vec2 origin{0.0f};       // world x, z of texel (0, 0)'s corner
  glm::vec2 size{1.0f};         // m covered along x and z
  float height = 0.0f;          // world y of the plane
  uint64_t version = 0;         // changes when the texture's content does (a reader may cache what it made of it); 0: unknown
};

// The atmosphere's aerial-perspective froxels (3D RGBA16F, atmosphere_params.h ATMOSPHERE_AERIAL_*; sample
// with atmosphere_common.glsl's atm_aerial_lookup), published from Stage::AfterOpaque; absent with
// --aerial-perspective fog (use the SceneLighting height fog then).
struct AerialPerspective {
  TextureHandle froxels;
};

struct StageContext {
  RenderGraph& graph;
  const FrameSnapshot& snapshot;
  gpu::Context& ctx;
  gpu::PipelineLibrary& library;
  UniformAllocator& uniforms;  // this frame's uniform memory (valid until the slot comes round again)
  UniformSlice frame_params;   // the engine's shared::FrameParams of this frame (camera, sun, sky)
  uint32_t slot = 0;           // frame-in-flight slot (index per-slot resources with it)
  TextureHandle hdr, depth;    // scene colour (R16G16B16A16F) and depth (D32F, reversed-Z)
  TextureHandle output;        // AfterTonemap only: the frame's target
  VkFormat output_format = VK_FORMAT_UNDEFINED;  // the target's format (swapchain or offscreen)
  LightDepth light_depth;       // the geometry's depth from the key light (every stage; invalid: none)
  // What features publish for what comes after them (stage_resources.h): a shadow caster's LightShadowMap
  // at Stage::BeforeScene (the geometry reads it), the engine's AerialPerspective from Stage::AfterOpaque.
  StageResources resources;
};

class RenderFeature {
 public:
  virtual ~RenderFeature() = default;
  // Called once by the renderer the feature is added to. Throws cumulo::Error on failure (a shader
  // that does not compile names the file and line).
  virtual void create_gpu(GpuServices&) {}
  // Called before the context goes away, with the device idle; also right after a create_gpu that threw, to
  // free what it had made (so it must cope with a partial create).
  virtual void destroy_gpu() {}
  // Called for every stage of every frame, in Stage order, features in the order they were added.
  virtual void add_passes(Stage, StageContext&) {}
};

}  // namespace cumulo::render
