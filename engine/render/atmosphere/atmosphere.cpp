#include "engine/render/atmosphere/atmosphere.h"

#include <algorithm>
#include <cmath>

#include "engine/core/color.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "engine/scene/serialization.h"

namespace cumulo::render {
namespace {

constexpr float kPi = 3.14159265358979f;

float rayleigh_phase(float nu) { return 3.0f / (16.0f * kPi) * (1.0f + nu * nu); }
// Cornette-Shanks (Bruneton's and Hillaire's Mie phase).
float mie_phase(float g, float nu) {
  const float k = 3.0f / (8.0f * kPi) * (1.0f - g * g) / (2.0f + g * g);
  return k * (1.0f + nu * nu) / std::pow(std::max(1.0f + g * g - 2.0f * g * nu, 1e-6f), 1.5f);
}

// Distance along (r, mu) to the sphere of radius R: the far root (from inside), or -1 for a miss.
float distance_to_sphere(float r, float mu, float R) {
  const float disc = r * r * (mu * mu - 1.0f) + R * R;
  if (disc < 0.0f) return -1.0f;
  return -r * mu + std::sqrt(disc);
}
// True when the ray from radius r with zenith cosine mu meets the ground (bottom sphere) first.
bool hits_ground(float r, float mu, float Rb) { return mu < 0.0f && r * r * (mu * mu - 1.0f) + Rb * Rb >= 0.0f; }
// Zenith cosine of the ground's horizon seen from radius r.
float horizon_mu(float r, float Rb) { return -std::sqrt(std::max(0.0f, 1.0f - (Rb / r) * (Rb / r))); }
float distance_to_ground(float r, float mu, float Rb) {
  return -r * mu - std::sqrt(std::max(r * r * (mu * mu - 1.0f) + Rb * Rb, 0.0f));
}

glm::vec3 vec3_of(const JsonView& v) {
  const glm::vec3 x = v.as_vec3();
  for (int i = 0; i < 3; ++i)
    if (!(x[i] >= 0.0f) || x[i] > 1.0f) v.fail("expected three numbers in 0..1");
  return x;
}

}  // namespace

std::filesystem::path default_atmosphere_file() { return repo_root() / "content/atmosphere/earth.json"; }

AtmosphereParams load_atmosphere(const std::filesystem::path& file) {
  const JsonDocument doc = load_json_file(file);
  const JsonView v = doc.view();
  if (!v.is_object()) v.fail("expected an object (an atmosphere preset)");
  scene::check_keys(v, {"$schema", "description", "bottom_radius_km", "top_radius_km", "rayleigh", "mie", "ozone", "ground_albedo",
                "sun_angular_radius_deg", "moon"});
  AtmosphereParams p;
  p.bottom_radius_km = v["bottom_radius_km"].as_float_in(1.0f, 1e5f);
  p.top_radius_km = v["top_radius_km"].as_float_in(1.0f, 1e5f);
  if (!(p.top_radius_km > p.bottom_radius_km + 1.0f)) v["top_radius_km"].fail("expected at least 1 km above bottom_radius_km");
  const JsonView r = v["rayleigh"];
  scene::check_keys(r, {"scattering", "scale_height_km"});
  p.rayleigh_scattering = vec3_of(r["scattering"]);
  p.rayleigh_scale_height_km = r["scale_height_km"].as_float_in(0.01f, 100.0f);
  const JsonView m = v["mie"];
  scene::check_keys(m, {"scattering", "extinction", "scale_height_km", "g"});
  p.mie_scattering = m["scattering"].as_float_in(0.0f, 1.0f);
  p.mie_extinction = m["extinction"].as_float_in(0.0f, 1.0f);
  if (p.mie_extinction < p.mie_scattering) m["extinction"].fail("expected at least the scattering (extinction = scattering + absorption)");
  p.mie_scale_height_km = m["scale_height_km"].as_float_in(0.01f, 100.0f);
  p.mie_g = m["g"].as_float_in(-0.99f, 0.99f);
  const JsonView o = v["ozone"];
  scene::check_keys(o, {"absorption", "center_km", "width_km"});
  p.ozone_absorption = vec3_of(o["absorption"]);
  p.ozone_center_km = o["center_km"].as_float_in(0.0f, 1000.0f);
  p.ozone_width_km = o["width_km"].as_float_in(0.01f, 1000.0f);
  p.ground_albedo = vec3_of(v["ground_albedo"]);
  p.sun_angular_radius_deg = v["sun_angular_radius_deg"].as_float_in(0.01f, 10.0f);
  if (v.has("moon")) {
    const JsonView mo = v["moon"];
    scene::check_keys(mo, {"fraction_of_sun", "albedo_tint"});
    p.moon_fraction = mo["fraction_of_sun"].as_float_in(0.0f, 1.0f);
    p.moon_tint = vec3_of(mo["albedo_tint"]);
  }
  return p;
}

Atmosphere::Atmosphere(const AtmosphereParams& p) : p_(p) {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  trans_.resize(size_t(kTw) * kTh);
  // Rows linear in the distance to the horizon, rho = sqrt(r^2 - Rb^2) (Bruneton 2017): dense near the
  // ground, where the air is.
  const float rho_max = std::sqrt(Rt * Rt - Rb * Rb);
  for (int j = 0; j < kTh; ++j)
    for (int i = 0; i < kTw; ++i) {
      const float rho = rho_max * float(j) / float(kTh - 1);
      const float r = std::sqrt(rho * rho + Rb * Rb);
      // Only rays above the ground's horizon at r (the rest see none), denser toward that horizon where
      // the transmittance changes fastest: mu = mu_h + u^2 (1 - mu_h).
      const float mu_h = horizon_mu(r, Rb), u = float(i) / float(kTw - 1);
      trans_[size_t(j) * kTw + i] = transmittance_exact(r, std::min(1.0f, mu_h + u * u * (1.0f - mu_h) + 1e-6f));
    }
  // psi_ms (Hillaire 2020, eq. 5-10): second-order light from 64 directions around the point, each
  // lit by the sun (isotropic phase, unit irradiance) and the ground, times 1 / (1 - f_ms).
  ms_.resize(size_t(kMs) * kMs);
  constexpr int kDirs = 8, kSteps = 20;
  for (int j = 0; j < kMs; ++j)
    for (int i = 0; i < kMs; ++i) {
      const float r = Rb + (Rt - Rb) * (float(j) + 0.5f) / float(kMs);
      const float mu_s = -1.0f + 2.0f * (float(i) + 0.5f) / float(kMs);
      const glm::vec3 pos(0.0f, r, 0.0f), sun(std::sqrt(std::max(0.0f, 1.0f - mu_s * mu_s)), mu_s, 0.0f);
      glm::vec3 l2(0.0f), fms(0.0f);
      for (int a = 0; a < kDirs; ++a)
        for (int b = 0; b < kDirs; ++b) {
          const float cos_t = 1.0f - 2.0f * (float(a) + 0.5f) / float(kDirs), phi = 2.0f * kPi * (float(b) + 0.5f) / float(kDirs);
          const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
          const glm::vec3 d(sin_t * std::cos(phi), cos_t, sin_t * std::sin(phi));
          const bool ground = hits_ground(r, cos_t, Rb);
          const float t_max = ground ? distance_to_ground(r, cos_t, Rb) : distance_to_sphere(r, cos_t, Rt);
          const float dt = t_max / float(kSteps);
          glm::vec3 T(1.0f);
          for (int s = 0; s < kSteps; ++s) {
            const glm::vec3 q = pos + d * ((float(s) + 0.5f) * dt);
            const float rq = glm::length(q), h = rq - Rb;
            const glm::vec3 sigma_s = p_.rayleigh_scattering * std::exp(-h / p_.rayleigh_scale_height_km) +
                                      glm::vec3(p_.mie_scattering * std::exp(-h / p_.mie_scale_height_km));
            const glm::vec3 ext = extinction(h);
            const glm::vec3 step_t = glm::exp(-ext * dt);
            const glm::vec3 integ = (glm::vec3(1.0f) - step_t) / glm::max(ext, glm::vec3(1e-9f));  // int T over the step
            const glm::vec3 ts = transmittance_lut(rq, glm::dot(q, sun) / rq);
            l2 += T * sigma_s * ts * (1.0f / (4.0f * kPi)) * integ;
            fms += T * sigma_s * integ;
            T *= step_t;
          }
          if (ground) {
            const glm::vec3 g = pos + d * t_max, n = glm::normalize(g);
            const float ndl = std::max(glm::dot(n, sun), 0.0f);
            l2 += T * transmittance_lut(Rb, glm::dot(n, sun)) * ndl * p_.ground_albedo / kPi;
          }
        }
      l2 /= float(kDirs * kDirs);
      fms /= float(kDirs * kDirs);
      ms_[size_t(j) * kMs + i] = l2 / (glm::vec3(1.0f) - glm::min(fms, glm::vec3(0.99f)));
    }
}

glm::vec3 Atmosphere::extinction(float h) const {
  const float hr = std::exp(-std::max(h, 0.0f) / p_.rayleigh_scale_height_km);
  const float hm = std::exp(-std::max(h, 0.0f) / p_.mie_scale_height_km);
  const float ho = std::max(0.0f, 1.0f - std::abs(h - p_.ozone_center_km) / (0.5f * p_.ozone_width_km));
  return p_.rayleigh_scattering * hr + glm::vec3(p_.mie_extinction * hm) + p_.ozone_absorption * ho;
}

glm::vec3 Atmosphere::transmittance_exact(float r, float mu) const {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  r = std::clamp(r, Rb, Rt);
  if (hits_ground(r, mu, Rb)) return glm::vec3(0.0f);
  const float t_max = std::max(distance_to_sphere(r, mu, Rt), 0.0f);
  constexpr int kSteps = 64;
  const float dt = t_max / float(kSteps);
  glm::vec3 od(0.0f);
  for (int s = 0; s < kSteps; ++s) {
    const float t = (float(s) + 0.5f) * dt;
    const float rq = std::sqrt(r * r + t * t + 2.0f * r * mu * t);
    od += extinction(rq - Rb) * dt;
  }
  return glm::exp(-od);
}

glm::vec3 Atmosphere::transmittance_lut(float r, float mu) const {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  r = std::clamp(r, Rb, Rt);
  // The table cannot hold the ground's edge sharply: below the horizon of r there is no light.
  if (hits_ground(r, mu, Rb)) return glm::vec3(0.0f);
  const float mu_h = horizon_mu(r, Rb);
  const float u = std::sqrt(std::clamp((mu - mu_h) / (1.0f - mu_h), 0.0f, 1.0f));
  const float x = u * float(kTw - 1);
  const float rho = std::sqrt(std::max(r * r - Rb * Rb, 0.0f)), rho_max = std::sqrt(Rt * Rt - Rb * Rb);
  const float y = std::clamp(rho / rho_max * float(kTh - 1), 0.0f, float(kTh - 1));
  const int x0 = std::min(int(x), kTw - 2), y0 = std::min(int(y), kTh - 2);
  const float fx = x - float(x0), fy = y - float(y0);
  auto at = [&](int i, int j) { return trans_[size_t(j) * kTw + i]; };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

glm::vec3 Atmosphere::transmittance(float r, float mu) const { return transmittance_lut(r, mu); }

glm::vec3 Atmosphere::multiple_scattering(float r, float mu_s) const {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  const float x = std::clamp((mu_s + 1.0f) * 0.5f * float(kMs) - 0.5f, 0.0f, float(kMs - 1));
  const float y = std::clamp((r - Rb) / (Rt - Rb) * float(kMs) - 0.5f, 0.0f, float(kMs - 1));
  const int x0 = std::min(int(x), kMs - 2), y0 = std::min(int(y), kMs - 2);
  const float fx = x - float(x0), fy = y - float(y0);
  auto at = [&](int i, int j) { return ms_[size_t(j) * kMs + i]; };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

Atmosphere::Inscatter Atmosphere::inscatter(float r, glm::vec3 dir, glm::vec3 sun_dir, float irradiance, float t_max,
                                             int steps) const {
  const float Rb = p_.bottom_radius_km;
  const glm::vec3 pos(0.0f, r, 0.0f);
  const float nu = glm::dot(dir, sun_dir);
  const float pr = rayleigh_phase(nu), pm = mie_phase(p_.mie_g, nu);
  Inscatter out{glm::vec3(0.0f), glm::vec3(1.0f)};
  float t0 = 0.0f;
  for (int s = 0; s < steps; ++s) {
    // Steps grow with the square of the index: dense near the viewer, where the air is.
    const float t1 = t_max * float((s + 1) * (s + 1)) / float(steps * steps);
    const float dt = t1 - t0, t = 0.5f * (t0 + t1);
    t0 = t1;
    const glm::vec3 q = pos + dir * t;
    const float rq = glm::length(q), h = rq - Rb;
    const float mu_s = glm::dot(q, sun_dir) / rq;
    const glm::vec3 sr = p_.rayleigh_scattering * std::exp(-h / p_.rayleigh_scale_height_km);
    const float sm = p_.mie_scattering * std::exp(-h / p_.mie_scale_height_km);
    const glm::vec3 ext = extinction(h);
    const glm::vec3 ts = transmittance_lut(rq, mu_s);
    const glm::vec3 S = irradiance * ((sr * pr + glm::vec3(sm * pm)) * ts + (sr + glm::vec3(sm)) * multiple_scattering(rq, mu_s));
    const glm::vec3 step_t = glm::exp(-ext * dt);
    out.radiance += out.transmittance * S * (glm::vec3(1.0f) - step_t) / glm::max(ext, glm::vec3(1e-9f));
    out.transmittance *= step_t;
  }
  return out;
}

glm::vec3 Atmosphere::sky_radiance(float altitude_km, glm::vec3 dir, glm::vec3 sun_dir, float irradiance) const {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  const float r = std::clamp(Rb + std::max(altitude_km, 0.001f), Rb, Rt - 0.001f);
  dir = glm::normalize(dir);
  sun_dir = glm::normalize(sun_dir);
  const float mu = dir.y;
  const bool ground = hits_ground(r, mu, Rb);
  const float t_max = ground ? distance_to_ground(r, mu, Rb) : distance_to_sphere(r, mu, Rt);
  const Inscatter in = inscatter(r, dir, sun_dir, irradiance, t_max, 40);
  glm::vec3 L = in.radiance;
  if (ground) {
    const glm::vec3 g = glm::normalize(glm::vec3(0.0f, r, 0.0f) + dir * t_max);
    const float ndl = std::max(glm::dot(g, sun_dir), 0.0f);
    L += in.transmittance * irradiance * transmittance_lut(Rb, glm::dot(g, sun_dir)) * ndl * p_.ground_albedo / kPi;
  }
  return L;
}

Atmosphere::Inscatter Atmosphere::aerial_perspective(float altitude_km, glm::vec3 dir, glm::vec3 sun_dir, float irradiance,
                                                     float distance_km) const {
  const float Rb = p_.bottom_radius_km, Rt = p_.top_radius_km;
  const float r = std::clamp(Rb + std::max(altitude_km, 0.001f), Rb, Rt - 0.001f);
  return inscatter(r, glm::normalize(dir), glm::normalize(sun_dir), irradiance, std::max(distance_km, 0.0f), 64);
}

float Atmosphere::night_weight(float sun_elevation_deg) { return std::clamp((-sun_elevation_deg - 4.0f) / 8.0f, 0.0f, 1.0f); }
float Atmosphere::moon_weight(float sun_elevation_deg) const { return night_weight(sun_elevation_deg) * p_.moon_fraction; }

SceneLighting Atmosphere::lighting(const scene::SunLight& sun, float camera_altitude_m) const {
  SceneLighting c;
  c.source = "atmosphere";
  const float h = std::max(camera_altitude_m, 0.0f) * 0.001f;
  const float r = p_.bottom_radius_km + h;
  const glm::vec3 key = glm::normalize(sun.direction);
  const float E = p_.solar_irradiance;
  // Night: the sun well below the horizon leaves the moon (opposite the sun: a full moon) as the light,
  // a small fraction of sunlight, through the same atmosphere. In between, both add (twilight).
  const glm::vec3 moon = -key;
  const float night = night_weight(sun.elevation_deg);
  auto sky = [&](glm::vec3 dir) {
    glm::vec3 L = sky_radiance(h, dir, key, E);
    if (night > 0.0f) L += sky_radiance(h, dir, moon, E * moon_weight(sun.elevation_deg));
    return L + kAirglow * glm::vec3(1.0f, 1.2f, 2.0f);  // airglow and starlight: night is never black
  };
  c.sky_zenith = sky({0.0f, 1.0f, 0.0f});
  glm::vec3 horizon(0.0f);
  for (int k = 0; k < 8; ++k) {
    const float a = 2.0f * kPi * float(k) / 8.0f;
    horizon += sky(glm::vec3(std::cos(a), 0.035f, std::sin(a)));
  }
  c.sky_horizon = horizon / 8.0f;
  // The upper hemisphere's mean: 8 bands of equal solid angle (sin e uniform, so the bright band near the
  // horizon gets its share) x 12 azimuths; within 6 % of a 32 x 64 quadrature at sun elevations 2.7-60 degrees
  // (atmosphere_test.cpp).
  // The same samples weighted by the sine of their elevation (the cosine to the up normal) give the horizontal
  // irradiance: E = 2 pi x their mean of L sin e, so E / pi = 2 x that mean.
  glm::vec3 mean(0.0f), cosine(0.0f);
  float weight = 0.0f;
  for (int v = 0; v < 8; ++v) {
    const float sin_e = (float(v) + 0.5f) / 8.0f, e = std::asin(sin_e);
    for (int k = 0; k < 12; ++k) {
      const float a = 2.0f * kPi * (float(k) + 0.5f) / 12.0f;
      const glm::vec3 L = sky(glm::vec3(std::cos(e) * std::cos(a), sin_e, std::cos(e) * std::sin(a)));
      mean += L;
      cosine += L * sin_e;
      weight += 1.0f;
    }
  }
  c.sky_mean = mean / weight;
  c.sky_irradiance = 2.0f * cosine / weight;
  // The key light: the sun, or past the middle of the twilight the moon (Lambertian units: a white
  // surface facing it shows E T / pi).
  if (night > 0.5f) {
    c.light_direction = moon;
    c.sun_radiance = night * E * p_.moon_fraction * transmittance_lut(r, moon.y) / kPi * p_.moon_tint;
  } else {
    c.light_direction = key;
    c.sun_radiance = E * transmittance_lut(r, key.y) / kPi * sun.top_of_atmosphere;
  }
  // The ground seen below the horizon: its albedo under the sun and the sky (the sky's horizontal irradiance).
  c.ground = p_.ground_albedo * (c.sun_radiance * std::max(c.light_direction.y, 0.0f) + c.sky_irradiance);
  c.ambient = 1.0f;
  // Exposure meter: the key light on a grey card plus the sky, held to 1 by day (the renderer's units are
  // set for the noon sun); the eye adapts only partly (the 0.6 power: dusk stays darker than day, night
  // darker than dusk), at most 32x.
  const float level = 0.05f * luminance(c.sun_radiance) * std::max(c.light_direction.y, 0.0f) + 0.5f * luminance(c.sky_zenith);
  c.exposure = std::clamp(std::pow(0.1f / std::max(level, 1e-6f), 0.6f), 1.0f, 32.0f);
  c.fog_density = 0.00004f;
  c.fog_falloff = 0.001f;
  return c;
}

}  // namespace cumulo::render
