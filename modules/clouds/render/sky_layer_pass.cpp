// The weather-driven 2.5D sky (sky_layer.h) as a frame pass (cloud_frame_pass.h): after the clouds' march, whose
// opaque clouds hide it, its colour and depth join the composite's inputs, which orders them against the voxel clouds. Drawn with
// --cloud-sky on, or auto in a level with a WeatherScheduler.
#include <memory>

#include "modules/clouds/render/cloud_frame_pass.h"
#include "modules/clouds/render/sky_layer.h"
#include "modules/clouds/scene/cloudscape_assets.h"

namespace cumulo::clouds::render {
namespace {

class SkyLayerPass final : public CloudFramePass {
 public:
  bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options, const CloudLevelFacts& level) override {
    if (!options.sky.value_or(level.has_weather_scheduler)) return false;
    sky_ = std::make_unique<SkyLayer>(g.ctx, g.library, prepare_sky_noise());
    options_ = &options;
    return true;
  }
  void destroy_gpu() override { sky_.reset(); }

  void add_before_composite(cumulo::render::StageContext& stage, const CloudFrame& frame, const CloudPassOutputs& voxel,
                            CloudFrameInputs& in) override {
    if (options_->reference_comparable) return;
    const SkyLayer::Outputs o = sky_->add_passes(stage.graph, frame.sky, in, stage.depth,
                                                 options_->sky_occlusion ? voxel : CloudPassOutputs{});
    in.sky_color = o.color;
    in.sky_depth = o.depth;
  }
  cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) override { return c.stage.hdr; }

 private:
  std::unique_ptr<SkyLayer> sky_;
  const CloudRenderOptions* options_ = nullptr;
};

}  // namespace

std::unique_ptr<CloudFramePass> make_sky_layer_pass() { return std::make_unique<SkyLayerPass>(); }

}  // namespace cumulo::clouds::render
