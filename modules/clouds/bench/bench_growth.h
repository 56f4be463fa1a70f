#pragma once
// `cumulo bench`'s evolving view (issue 26): a cloud that grows during play (gameplay::CloudGrowth), measured from
// a camera that sees it: what one simulation step, the distance field and the attributes cost on the GPU (timed
// apart), what the light grid's rebuild costs, and the frame by the wall clock while the cloud holds and while it
// grows at the renderer's pace (a step one frame, the images the next: CloudGrowthRuntime::plan). From these, the
// amortized cost per frame at the component's rate (steps per second of play) and how long the cloud takes to build.
#include <string>

#include <nlohmann/json.hpp>

namespace cumulo::app {
class HeadlessSession;
}
namespace cumulo::clouds::render {
class CloudFeature;
}

namespace cumulo::clouds::bench {

struct GrowthFigures {
  bool measured = false;
  std::string why_not;  // when not measured
  std::string camera, spec;
  int cells[3] = {0, 0, 0}, voxels[3] = {0, 0, 0};
  double voxel_m = 0;
  double steps_per_second = 0;  // of play (CloudGrowth's speed / the spec's dt)
  int last_step = 0;
  double build_seconds = 0;  // of play, from the start to the last step
  // GPU ms (medians): one step; the distance field, the attributes and the images (the apart order); a whole update
  // as the frames record it (interleaved, summed over its frames); the light grid's passes in the update's last frame (a
  // rebuild, or with the sweep its first levels).
  double step_ms = 0, sdf_ms = 0, attributes_ms = 0, images_ms = 0, update_ms = 0, light_grid_ms = 0;
  // The frames an update is spread over: the option (0: none, the update in the frame that steps) and as measured.
  int update_frames_setting = 0;
  double update_frames = 0;
  // Wall-clock ms per frame (median): the cloud held; growing (a step, then its update); the frames that step, the
  // frames of an update, the update's last (the images and the light grid); the worst frame while it grows.
  double held_ms = 0, growing_ms = 0, stepping_ms = 0, updating_ms = 0, images_frame_ms = 0, worst_ms = 0;
  // The growth's cost per frame at its rate: steps_per_second x (step + update + light grid) / the held frame rate.
  double amortized_ms = 0;
  double fps_held() const { return held_ms > 0 ? 1000.0 / held_ms : 0; }
  // Frames per second while it grows at its rate: a second of play holds steps_per_second steps and as many updates.
  double fps_growing() const;
};

// Measures the level's first growing cloud from `camera` at the session's size in `mode` (Hz), `frames` frames per
// sample set. Leaves the cloud where it was (held, its target where the component had it).
GrowthFigures measure_growth(app::HeadlessSession& session, render::CloudFeature& feature, const std::string& camera,
                             int mode, int frames);
std::string growth_markdown(const GrowthFigures& g, unsigned width, unsigned height, int mode);
nlohmann::ordered_json growth_json(const GrowthFigures& g);

}  // namespace cumulo::clouds::bench
