#pragma once
// JSON forms of the scene components, registered by name with the ECS ComponentRegistry.
// Every error names the file and JSON path ("level.json: $.entities[2].components.Camera.fov_y_deg: ...").
// Unknown keys inside a component are errors too (a typo must not silently keep a default).
//
//   "Transform": {"position": [x, y, z],                 metres (default 0, 0, 0)
//                 "rotation": [x, y, z, w]               unit quaternion, glTF order   } at most one of
//               | "euler_deg": [pitch, yaw, roll]        degrees, see euler_degrees_to_quat }  these three
//               | "look_at": [x, y, z],                  a world point the -Z axis faces }  (default identity)
//                 "scale": [x, y, z] or s}               (default 1)
//   "Camera":    {"fov_y_deg": 60, "near": 0.1, "far": 50000}       fov in (1, 179), 0 < near < far
//   "ModelRef":  {"path": "terrain.glb", "cast_shadows": true}      path relative to the level file
//   "TimeOfDay": {"hours": 16.5, "day_of_year": 240, "latitude_deg": 34.05, "north_deg": 0, "hours_per_second": 0}
//   "Sun":       {"color": [1, 1, 1], "illuminance": 1}
//   "Ocean":     {"sea_level": 0, "color": [0.02, 0.12, 0.2]}
// Every member is optional and defaults to the struct's default (components.h).
#include <initializer_list>
#include <string>

#include "engine/core/json.h"
#include "engine/ecs/serialize.h"

namespace cumulo::scene {

void register_components(ecs::ComponentRegistry& registry);

// Fails on any key of the object `v` not in `allowed`, naming it and listing the allowed ones.
void check_keys(const JsonView& v, std::initializer_list<const char*> allowed);

}  // namespace cumulo::scene
