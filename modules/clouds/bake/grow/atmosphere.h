#pragma once
// The ambient atmosphere a grown cloud rises through: temperature, pressure, potential temperature and
// vapour per height level (Harris et al. 2003, "Simulation of Cloud Dynamics on Graphics Hardware",
// section 2; Miyazaki et al. 2001, "Simulation of cumuliform clouds based on computational fluid
// dynamics", section 3).
//
// Scale: a game asset is a few hundred metres tall, a real cumulus a few kilometres. The solver runs in
// physical units on cells of `scale` physical metres per game metre, so the spec's heights (cloud base,
// inversion, tropopause) are written in the asset's own box metres and the physics stays the real one.
//
//   T(z)  = ground temperature - lapse * z, plus `strength` K over the inversion layer, isothermal
//           above the tropopause (a stable lid: a cumulonimbus spreads into an anvil under it)
//   p(z)  = hydrostatic: dp/dz = -g p / (R T)
//   Pi(z) = (p / p0)^kappa (Exner), theta = T / Pi, qv = RH(z) qs(T, p)
//   qs    = 380.2 / p exp(17.67 Tc / (Tc + 243.5))  (Harris eq. 12; Tc in Celsius, p in Pa, kg/kg)
#include <vector>

namespace cumulo::clouds::grow {

inline constexpr float kGravity = 9.81f;        // m/s^2
inline constexpr float kGasConstantAir = 287.0f;  // J / (kg K)
inline constexpr float kVapourGasConstant = 461.5f;  // J / (kg K)
inline constexpr float kHeatCapacityAir = 1005.0f;  // cp, J / (kg K)
inline constexpr float kLatentHeat = 2.501e6f;  // J/kg, vaporisation
inline constexpr float kKappa = 0.286f;         // R / cp
inline constexpr float kReferencePressure = 100000.0f;  // Pa, potential temperature reference

// Saturation mixing ratio (kg/kg) at temperature `t_kelvin` and pressure `p_pa`.
float saturation_mixing_ratio(float t_kelvin, float p_pa);

// Everything in physical metres and kelvin; humidity as relative humidity 0..1.
struct AtmosphereSettings {
  float ground_temperature = 299.0f;  // K at the box's floor
  float ground_pressure = 100000.0f;  // Pa
  float lapse_rate = 0.0075f;         // K/m below the inversion (environmental)
  float upper_lapse_rate = 0.0065f;   // K/m between the inversion and the tropopause
  float inversion_height = 1.0e9f;    // m; none by default
  float inversion_thickness = 200.0f;
  float inversion_strength = 0.0f;    // K of warming across the layer
  float tropopause_height = 1.0e9f;   // m; isothermal above
  float humidity_ground = 0.8f;       // relative humidity at the floor
  float humidity_top = 0.4f;          // at the inversion (or the box top), linear in between
  float humidity_above_inversion = 0.25f;
};

class Atmosphere {
 public:
  // Levels at heights (j + 0.5) * cell, j = 0 .. levels - 1 (cell centres of the solver's grid).
  Atmosphere(const AtmosphereSettings& s, int levels, float cell);

  int levels() const { return int(temperature_.size()); }
  float temperature(int j) const { return temperature_[clampj(j)]; }
  float pressure(int j) const { return pressure_[clampj(j)]; }
  float exner(int j) const { return exner_[clampj(j)]; }
  float theta(int j) const { return theta_[clampj(j)]; }
  float vapour(int j) const { return vapour_[clampj(j)]; }
  // Lifting condensation level estimate (m): where a parcel from the floor saturates.
  float condensation_level() const { return lcl_; }

 private:
  int clampj(int j) const { return j < 0 ? 0 : (j >= levels() ? levels() - 1 : j); }
  std::vector<float> temperature_, pressure_, exner_, theta_, vapour_;
  float lcl_ = 0.0f;
};

}  // namespace cumulo::clouds::grow
