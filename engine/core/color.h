#pragma once
// Rec. 709 luminance of linear RGB: the one weighting of colour into brightness the engine and its modules share
// (the exposure meter, the fidelity metric, the clouds' sky light kept at a luminance in another hue).
#include <glm/glm.hpp>

namespace cumulo {

inline float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace cumulo
