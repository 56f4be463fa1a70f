#pragma once
// The soak's camera path (`cumulo soak`): a closed loop through every camera of the level (the ground, the
// cloudscape, the storm cloud's chamber...) and the centre of every WeatherZone, each put where it lengthens the
// loop least, flown at a constant speed (a Catmull-Rom spline through them, parameterized by arc length), looking
// ahead along it. The loop takes the same frames every lap, so the soak compares frame times over the same stretch.
//
//   const SoakPath path = make_soak_path(world);
//   scene::Transform t = path.transform(0.25);   // a quarter of the way round
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/world.h"
#include "engine/scene/components.h"

namespace cumulo::clouds::soak {

class SoakPath {
 public:
  // At least two distinct points (throws cumulo::Error otherwise).
  explicit SoakPath(std::vector<glm::vec3> points);
  const std::vector<glm::vec3>& points() const { return points_; }
  float length() const { return length_; }
  // u in [0, 1) of the loop's length (wrapped): the point there, and a camera there looking 2 % further on.
  glm::vec3 position(double u) const;
  scene::Transform transform(double u) const;

 private:
  glm::vec3 spline(size_t segment, float t) const;
  std::vector<glm::vec3> points_;
  std::vector<float> arc_;  // cumulative length at each of kSamples samples per segment
  float length_ = 0.0f;
};

// The loop through the level's cameras (entity order) and zone centres (see above); throws when the level has
// fewer than two distinct such points.
SoakPath make_soak_path(const ecs::World& world);

}  // namespace cumulo::clouds::soak
