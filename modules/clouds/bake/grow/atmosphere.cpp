#include "modules/clouds/bake/grow/atmosphere.h"

#include <algorithm>
#include <cmath>

namespace cumulo::clouds::grow {

float saturation_mixing_ratio(float t_kelvin, float p_pa) {
  const float tc = t_kelvin - 273.15f;
  return 380.2f / std::max(p_pa, 100.0f) * std::exp(17.67f * tc / std::max(tc + 243.5f, 1.0f));
}

namespace {

float ambient_temperature(const AtmosphereSettings& s, float z) {
  const float zi = std::min(z, s.tropopause_height);
  float t = s.ground_temperature - s.lapse_rate * std::min(zi, s.inversion_height);
  if (zi > s.inversion_height) {
    const float in_layer = std::min(zi - s.inversion_height, s.inversion_thickness);
    t += s.inversion_strength * in_layer / std::max(s.inversion_thickness, 1.0f);
    t -= s.upper_lapse_rate * std::max(0.0f, zi - s.inversion_height - s.inversion_thickness);
  }
  return t;
}

float ambient_humidity(const AtmosphereSettings& s, float z, float top) {
  const float h = std::min(s.inversion_height, top);
  if (z <= h) return s.humidity_ground + (s.humidity_top - s.humidity_ground) * (z / std::max(h, 1.0f));
  return s.humidity_above_inversion;
}

}  // namespace

Atmosphere::Atmosphere(const AtmosphereSettings& s, int levels, float cell) {
  temperature_.resize(levels), pressure_.resize(levels), exner_.resize(levels), theta_.resize(levels),
      vapour_.resize(levels);
  const float top = levels * cell;
  // Hydrostatic pressure integrated in small sub-steps from the floor.
  double p = s.ground_pressure, z = 0.0;
  const int sub = 8;
  for (int j = 0; j < levels; ++j) {
    const double target = (j + 0.5) * cell;
    const double dz = (target - z) / sub;
    for (int k = 0; k < sub; ++k) {
      const double t = ambient_temperature(s, float(z + 0.5 * dz));
      p *= std::exp(-kGravity * dz / (kGasConstantAir * t));
      z += dz;
    }
    const float t = ambient_temperature(s, float(target));
    temperature_[j] = t;
    pressure_[j] = float(p);
    exner_[j] = std::pow(float(p) / kReferencePressure, kKappa);
    theta_[j] = t / exner_[j];
    vapour_[j] = std::clamp(ambient_humidity(s, float(target), top), 0.0f, 1.0f) * saturation_mixing_ratio(t, float(p));
  }
  // Espy's estimate: 125 m per kelvin of dew-point depression (Magnus dew point of the floor air).
  const float tc = s.ground_temperature - 273.15f;
  const float g = std::log(std::max(s.humidity_ground, 0.01f)) + 17.62f * tc / (243.12f + tc);
  const float dew = 243.12f * g / (17.62f - g);
  lcl_ = std::max(0.0f, 125.0f * (tc - dew));
}

}  // namespace cumulo::clouds::grow
