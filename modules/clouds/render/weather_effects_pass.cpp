// The lightning bolts and the rain (cloud_effects.h) as a frame pass (cloud_frame_pass.h): the frame's
// bolts, and a rain column under each raining cloud.
#include <algorithm>
#include <memory>

#include "modules/clouds/render/cloud_effects.h"
#include "modules/clouds/render/cloud_frame_pass.h"

namespace cumulo::clouds::render {
namespace {

class WeatherEffectsPass final : public CloudFramePass {
 public:
  bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options, const CloudLevelFacts&) override {
    effects_ = std::make_unique<CloudEffects>(g.ctx, g.library);
    options_ = &options;
    return true;
  }
  void destroy_gpu() override { effects_.reset(); }

  cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) override {
    const cumulo::render::StageContext& f = c.stage;
    if (options_->reference_comparable) return f.hdr;
    const CloudFrameInputs& in = c.in;
    CloudEffectsInputs fx;
    fx.camera = f.snapshot.camera;
    fx.time = f.snapshot.sim_time;
    fx.slot = f.slot;
    fx.bolts = c.frame.bolts;
    fx.rain_light = in.ambient_color * 0.3f + in.sun_color * 0.01f;  // under the cloud: mostly shadowed
    // Rain columns under precipitating clouds: below the centre of the box, 0.3 of its smaller side wide,
    // from the cloud base to sea level (the scene depth stops them at the terrain), fading with dissipation.
    for (size_t k = 0; k < in.instances.size() && options_->rain; ++k) {
      const CloudInstanceFrame& i = c.frame.instances.at(in.frame_instances.at(k));
      const float intensity = i.rain * (1.0f - std::clamp(i.dissipation, 0.0f, 1.0f));
      if (!(intensity > 0.0f)) continue;
      const CloudAsset& a = *in.instances[k].asset;
      const glm::vec3 base(0.5f * (a.bounds_min.x + a.bounds_max.x), a.bounds_min.y, 0.5f * (a.bounds_min.z + a.bounds_max.z));
      const glm::vec3 extent = a.bounds_max - a.bounds_min;
      fx.rain.push_back({i.position + glm::normalize(i.rotation) * (i.scale * base),
                         0.3f * i.scale * std::min(extent.x, extent.z), 0.0f, intensity});
    }
    if (fx.bolts.empty() && fx.rain.empty()) return f.hdr;
    return effects_->add_passes(f.graph, fx, f.hdr, f.depth, c.clouds);
  }

 private:
  std::unique_ptr<CloudEffects> effects_;
  const CloudRenderOptions* options_ = nullptr;
};

}  // namespace

std::unique_ptr<CloudFramePass> make_weather_effects_pass() { return std::make_unique<WeatherEffectsPass>(); }

}  // namespace cumulo::clouds::render
