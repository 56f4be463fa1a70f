// The light shafts (light_shafts.h) as a frame pass (cloud_frame_pass.h), with --cloud-light-shafts on.
#include <memory>

#include "modules/clouds/render/cloud_frame_pass.h"
#include "modules/clouds/render/light_shafts.h"

namespace cumulo::clouds::render {
namespace {

class LightShaftsPass final : public CloudFramePass {
 public:
  bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options, const CloudLevelFacts&) override {
    if (!options.light_shafts) return false;
    shafts_ = std::make_unique<LightShafts>(g.ctx, g.library);
    options_ = &options;
    return true;
  }
  void destroy_gpu() override { shafts_.reset(); }

  cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) override {
    const cumulo::render::StageContext& f = c.stage;
    if (options_->reference_comparable) return f.hdr;
    LightShaftInputs li;
    li.camera = f.snapshot.camera;
    li.slot = f.slot;
    li.sun_direction = c.in.sun_direction;
    li.sun_color = c.in.sun_color;
    li.haze_density = c.in.haze_density;
    li.haze_falloff = c.in.haze_falloff;
    return shafts_->add_passes(f.graph, li, f.hdr, f.depth, c.clouds, c.in.sky_color);
  }

 private:
  std::unique_ptr<LightShafts> shafts_;
  const CloudRenderOptions* options_ = nullptr;
};

}  // namespace

std::unique_ptr<CloudFramePass> make_light_shafts_pass() { return std::make_unique<LightShaftsPass>(); }

}  // namespace cumulo::clouds::render
