#include "modules/clouds/render/cloud_frame_pass.h"

namespace cumulo::clouds::render {

// A pass's maker (in its own file) and its line in the list: all a new frame pass adds here.
std::unique_ptr<CloudFramePass> make_sky_layer_pass();        // sky_layer_pass.cpp
std::unique_ptr<CloudFramePass> make_envelope_pass();         // envelope_pass.cpp
std::unique_ptr<CloudFramePass> make_weather_effects_pass();  // weather_effects_pass.cpp
std::unique_ptr<CloudFramePass> make_light_shafts_pass();     // light_shafts_pass.cpp

std::vector<std::unique_ptr<CloudFramePass>> make_cloud_frame_passes() {
  std::vector<std::unique_ptr<CloudFramePass>> passes;
  passes.push_back(make_sky_layer_pass());        // the weather-driven 2.5D sky (sky_layer.h)
  passes.push_back(make_envelope_pass());         // the Envelope method's orographic clouds (envelope_layer.h)
  passes.push_back(make_weather_effects_pass());  // lightning bolts and rain (cloud_effects.h)
  passes.push_back(make_light_shafts_pass());     // light shafts through gaps in the clouds (light_shafts.h)
  return passes;
}

}  // namespace cumulo::clouds::render
