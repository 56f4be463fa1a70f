#pragma once
// The physically based atmosphere (issue 10; Hillaire 2020, "A Scalable and Production Ready Sky and
// Atmosphere Rendering Technique", with Bruneton 2017's density profiles): the parameters of a preset
// (content/atmosphere/earth.json) and a CPU evaluation of the model: transmittance, the multiple-
// scattering term psi_ms of Hillaire's section 5.5 (as a small table), sky radiance along a view ray
// (single scattering of the sun plus psi_ms), and from them the frame's SceneLighting: the sun at the
// ground, the sky colours and the hemispheric ambient at every time of day, and a moonlit night.
// The GPU LUT passes compute the same integrals; this is their reference and the lighting's source.
//
// Units: lengths in km, coefficients per km, radiance in the renderer's units for a sun of irradiance
// `solar_irradiance` at the top of the atmosphere (render::kSunRadianceScale * pi: a white Lambertian
// surface under the noon sun shows about 3).
//
//   AtmosphereParams p = load_atmosphere("content/atmosphere/earth.json");
//   Atmosphere a(p);                                   // builds the transmittance and psi_ms tables
//   SceneLighting l = a.lighting(sun, camera_height_m);
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"
#include "engine/scene/sun.h"

namespace cumulo::render {

struct AtmosphereParams {
  float bottom_radius_km = 6360.0f;
  float top_radius_km = 6460.0f;
  glm::vec3 rayleigh_scattering{0.005802f, 0.013558f, 0.0331f};
  float rayleigh_scale_height_km = 8.0f;
  float mie_scattering = 0.003996f, mie_extinction = 0.0044f;
  float mie_scale_height_km = 1.2f;
  float mie_g = 0.8f;
  glm::vec3 ozone_absorption{0.00065f, 0.001881f, 0.000085f};
  float ozone_center_km = 25.0f, ozone_width_km = 30.0f;  // tent profile
  glm::vec3 ground_albedo{0.3f};
  float sun_angular_radius_deg = 0.2665f;
  float moon_fraction = 0.0015f;  // moonlight / sunlight (a full moon is ~1/400 000; brightened for the eye)
  glm::vec3 moon_tint{0.9f, 0.95f, 1.0f};
  float solar_irradiance = 9.42477796f;  // 3 pi: render::kSunRadianceScale x pi
};

// Reads a preset; throws cumulo::Error naming the file and the JSON path ("earth.json: $.mie.g: expected
// a number in -0.99..0.99") for a missing, malformed or out-of-range value.
AtmosphereParams load_atmosphere(const std::filesystem::path& file);
std::filesystem::path default_atmosphere_file();  // content/atmosphere/earth.json under the repo root

class Atmosphere {
 public:
  explicit Atmosphere(const AtmosphereParams& p);
  const AtmosphereParams& params() const { return p_; }

  // Extinction coefficient (per km) at altitude h (km).
  glm::vec3 extinction(float h_km) const;
  // Transmittance from radius r (km) toward zenith cosine mu to the top of the atmosphere (0 if the ray
  // hits the ground). Exact integral (numerical, 64 steps) and the table lookup used by the integrators.
  glm::vec3 transmittance_exact(float r_km, float mu) const;
  glm::vec3 transmittance(float r_km, float mu) const;
  // Hillaire's psi_ms at radius r and sun zenith cosine mu_s (table lookup): the multiple-scattering
  // contribution per unit of scattering coefficient and solar irradiance.
  glm::vec3 multiple_scattering(float r_km, float mu_s) const;
  // Radiance arriving at a point `altitude_km` above the ground from direction `dir` (world, +Y up),
  // the sun toward `sun_dir` with irradiance `irradiance` (renderer units); no sun disc.
  glm::vec3 sky_radiance(float altitude_km, glm::vec3 dir, glm::vec3 sun_dir, float irradiance) const;
  // Along a view ray over distance_km: the air's in-scattered radiance and its transmittance (the
  // aerial-perspective froxels' reference; Hillaire 2020 section 5.4).
  struct Inscatter {
    glm::vec3 radiance, transmittance;
  };
  Inscatter aerial_perspective(float altitude_km, glm::vec3 dir, glm::vec3 sun_dir, float irradiance,
                               float distance_km) const;

  // The frame's lighting at the camera's altitude: sun_radiance (at the ground, Lambertian units), sky
  // zenith and horizon colours (the horizon averaged over azimuth), ground colour, ambient 1 (the sky's
  // radiance is the ambient), and the moon as the light when the sun is below the horizon.
  SceneLighting lighting(const scene::SunLight& sun, float camera_altitude_m = 0.0f) const;
  // 0 by day .. 1 at night (the sun 4..12 degrees below the horizon): how much the moon counts.
  static float night_weight(float sun_elevation_deg);
  // The moon's irradiance as a fraction of the sun's now (night_weight x the preset's fraction).
  float moon_weight(float sun_elevation_deg) const;
  static constexpr float kAirglow = 0.0001f;  // x (1, 1.2, 2): airglow and starlight, night is never black

 private:
  glm::vec3 transmittance_lut(float r, float mu) const;
  // Single scattering through the transmittance LUT plus psi_ms from radius r along dir for t_max km.
  Inscatter inscatter(float r, glm::vec3 dir, glm::vec3 sun_dir, float irradiance, float t_max, int steps) const;
  AtmosphereParams p_;
  static constexpr int kTw = 128, kTh = 64, kMs = 32;
  std::vector<glm::vec3> trans_;  // kTw (mu) x kTh (r)
  std::vector<glm::vec3> ms_;     // kMs (mu_s) x kMs (r)
};

}  // namespace cumulo::render
