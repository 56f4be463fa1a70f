// The atmosphere model (engine/render/atmosphere): transmittance against the closed form of an
// exponential atmosphere, its table against the integral, the ground's shadow, the sky's colours at noon,
// sunset and night with stated invariants, the sun's reddening, psi_ms, and preset errors that name the place.
#include "engine/render/atmosphere/atmosphere.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/render/sky_model.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

scene::SunLight sun_at(float elevation_deg) {
  scene::SunLight s;
  const float e = glm::radians(elevation_deg);
  s.direction = glm::vec3(0.0f, std::sin(e), -std::cos(e));
  s.elevation_deg = elevation_deg;
  return s;
}
float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

const Atmosphere& earth() { return default_atmosphere(); }

TEST(Atmosphere, ZenithTransmittanceMatchesTheClosedForm) {
  const AtmosphereParams& p = earth().params();
  const float H = p.top_radius_km - p.bottom_radius_km;
  // Vertical optical depth of an exponential layer: sigma * Hs * (1 - exp(-H / Hs)); ozone's tent: sigma * width / 2.
  auto column = [&](float hs) { return hs * (1.0f - std::exp(-H / hs)); };
  const glm::vec3 od = p.rayleigh_scattering * column(p.rayleigh_scale_height_km) +
                       glm::vec3(p.mie_extinction * column(p.mie_scale_height_km)) + p.ozone_absorption * (0.5f * p.ozone_width_km);
  const glm::vec3 expected = glm::exp(-od);
  const glm::vec3 got = earth().transmittance_exact(p.bottom_radius_km, 1.0f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 0.002f) << c;
  std::printf("  zenith transmittance at sea level: %.3f %.3f %.3f\n", got.r, got.g, got.b);
  EXPECT_GT(got.r, got.b);  // blue is scattered most
}

TEST(Atmosphere, TableAgreesWithTheIntegralAndTheGroundShadows) {
  const AtmosphereParams& p = earth().params();
  float worst = 0.0f;
  for (float h : {0.0f, 1.0f, 5.0f, 30.0f, 90.0f})
    for (float mu : {1.0f, 0.5f, 0.2f, 0.05f, 0.0f}) {
      const float r = p.bottom_radius_km + h;
      const glm::vec3 a = earth().transmittance(r, mu), b = earth().transmittance_exact(r, mu);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(a[c] - b[c]));
    }
  EXPECT_LT(worst, 0.02f);
  EXPECT_EQ(earth().transmittance(p.bottom_radius_km + 1.0f, -0.3f), glm::vec3(0.0f));  // into the ground
  // At 10 km the horizon is about 3.2 degrees down: just above that the ray grazes but misses the ground.
  EXPECT_GT(earth().transmittance(p.bottom_radius_km + 10.0f, -0.05f).r, 0.0f);
  EXPECT_LT(earth().transmittance(p.bottom_radius_km, 0.02f).b, 0.2f * earth().transmittance(p.bottom_radius_km, 1.0f).b);
}

TEST(Atmosphere, SkyColoursAtNoonSunsetAndNight) {
  const SceneLighting noon = earth().lighting(sun_at(60.0f)), sunset = earth().lighting(sun_at(2.0f)),
                      twilight = earth().lighting(sun_at(-3.0f)), night = earth().lighting(sun_at(-25.0f));
  std::printf("  zenith noon %.3f %.3f %.3f, sunset horizon %.3f %.3f %.3f zenith %.3f %.3f %.3f\n", noon.sky_zenith.r,
              noon.sky_zenith.g, noon.sky_zenith.b, sunset.sky_horizon.r, sunset.sky_horizon.g, sunset.sky_horizon.b,
              sunset.sky_zenith.r, sunset.sky_zenith.g, sunset.sky_zenith.b);
  // Noon: a blue zenith (b > g > r), a paler horizon.
  EXPECT_GT(noon.sky_zenith.b, noon.sky_zenith.g);
  EXPECT_GT(noon.sky_zenith.g, noon.sky_zenith.r);
  EXPECT_GT(noon.sky_horizon.r / noon.sky_horizon.b, noon.sky_zenith.r / noon.sky_zenith.b);
  // Sunset: the horizon is redder than the zenith (red / blue at least 1.5x the zenith's).
  EXPECT_GT(sunset.sky_horizon.r / sunset.sky_horizon.b, 1.5f * sunset.sky_zenith.r / sunset.sky_zenith.b);
  // The sun itself reddens toward the horizon.
  EXPECT_GT(sunset.sun_radiance.r / sunset.sun_radiance.b, 2.0f * noon.sun_radiance.r / noon.sun_radiance.b);
  // Night is darker than twilight by at least 5x at the zenith; the key light is the moon, above the horizon.
  const float lt = luminance(twilight.sky_zenith), ln = luminance(night.sky_zenith);
  std::printf("  zenith luminance: noon %.4f, twilight (-3 deg) %.5f, night (-25 deg) %.6f (ratio %.1f)\n",
              luminance(noon.sky_zenith), lt, ln, lt / ln);
  EXPECT_GT(lt, 5.0f * ln);
  EXPECT_GT(ln, 0.0f);
  EXPECT_GT(night.light_direction.y, 0.0f);
  EXPECT_GT(luminance(night.sun_radiance), 0.0f);
  EXPECT_LT(luminance(night.sun_radiance), 0.01f * luminance(noon.sun_radiance));
  // The noon sun on a white surface: about the renderer's 3.
  EXPECT_GT(luminance(noon.sun_radiance), 2.0f);
  EXPECT_LT(luminance(noon.sun_radiance), 3.2f);
}

// The mean of the sky's radiance over the upper hemisphere weighted by weight(elevation) per solid angle, by a fine
// 32 x 64 quadrature in elevation and azimuth (d omega = cos(e) de da).
template <class Weight>
glm::vec3 hemisphere_mean(const scene::SunLight& s, Weight weight) {
  const double pi = 3.14159265358979;
  glm::dvec3 sum(0.0);
  double w = 0.0;
  for (int v = 0; v < 32; ++v) {
    const double e = (v + 0.5) / 32.0 * 0.5 * pi;
    for (int u = 0; u < 64; ++u) {
      const double a = (u + 0.5) / 64.0 * 2.0 * pi;
      const glm::vec3 d(float(std::cos(e) * std::cos(a)), float(std::sin(e)), float(std::cos(e) * std::sin(a)));
      const double k = weight(e) * std::cos(e);
      sum += glm::dvec3(earth().sky_radiance(0.0f, d, glm::normalize(s.direction), earth().params().solar_irradiance)) * k;
      w += k;
    }
  }
  return glm::vec3(sum / w);
}

// The sky's mean over the upper hemisphere (SceneLighting::sky_mean) against a fine quadrature of the same radiance:
// within 7 % per channel from a low sun to noon; and below 0.5 (zenith + horizon), which the horizon's bright band
// (and at a low sun the sun's glow in it) pulls up.
TEST(Atmosphere, SkyMeanIsTheUpperHemispheresMean) {
  for (float el : {2.7f, 15.0f, 60.0f}) {
    SCOPED_TRACE(el);
    const scene::SunLight s = sun_at(el);
    const SceneLighting c = earth().lighting(s);
    const glm::vec3 fine = hemisphere_mean(s, [](double) { return 1.0; });  // per solid angle
    std::printf("  sun %4.1f deg: sky mean %.4f %.4f %.4f, fine %.4f %.4f %.4f, 0.5 (zenith + horizon) %.4f %.4f %.4f\n", el, c.sky_mean.r,
                c.sky_mean.g, c.sky_mean.b, fine.r, fine.g, fine.b, 0.5f * (c.sky_zenith.r + c.sky_horizon.r),
                0.5f * (c.sky_zenith.g + c.sky_horizon.g), 0.5f * (c.sky_zenith.b + c.sky_horizon.b));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.sky_mean[k], fine[k], 0.07f * fine[k]);
    EXPECT_LT(luminance(c.sky_mean), 0.75f * luminance(0.5f * (c.sky_zenith + c.sky_horizon)));
  }
}

// The sky's horizontal irradiance / pi (SceneLighting::sky_irradiance, the light a ground reflects of the sky) against a
// fine quadrature of the cosine-weighted radiance: within 7 % per channel; below the hemisphere's mean (measured: 53-75 %
// of it), whose brightest band (the horizon's, at a low sun with the sun's glow) a horizontal ground sees at a grazing
// angle.
TEST(Atmosphere, SkyIrradianceIsTheCosineWeightedHemisphere) {
  for (float el : {2.7f, 15.0f, 60.0f}) {
    SCOPED_TRACE(el);
    const scene::SunLight s = sun_at(el);
    const SceneLighting c = earth().lighting(s);
    // E / pi = the cosine-weighted mean (the weights' integral over the hemisphere, pi, cancels the 1 / pi)
    const glm::vec3 fine = hemisphere_mean(s, [](double e) { return std::sin(e); });
    std::printf("  sun %4.1f deg: sky irradiance / pi %.4f %.4f %.4f, fine %.4f %.4f %.4f, sky mean %.4f %.4f %.4f\n", el,
                c.sky_irradiance.r, c.sky_irradiance.g, c.sky_irradiance.b, fine.r, fine.g, fine.b, c.sky_mean.r, c.sky_mean.g,
                c.sky_mean.b);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.sky_irradiance[k], fine[k], 0.07f * fine[k]);
    EXPECT_LT(luminance(c.sky_irradiance), 0.9f * luminance(c.sky_mean));
  }
}

TEST(Atmosphere, MultipleScatteringIsPositiveAndFadesWithTheSun) {
  const AtmosphereParams& p = earth().params();
  const glm::vec3 day = earth().multiple_scattering(p.bottom_radius_km, 0.8f), dusk = earth().multiple_scattering(p.bottom_radius_km, -0.2f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(day[c], 0.0f);
    EXPECT_LT(dusk[c], day[c]);
  }
  EXPECT_LT(day.b, 1.0f);
}

TEST(Atmosphere, BadPresetsNameTheFileAndThePlace) {
  const test::TempDir dir(test::test_temp_name("cumulo_atmosphere"));
  const std::string good = cumulo::read_file_text(default_atmosphere_file());
  auto refused = [&](const std::string& name, const std::string& text, const std::string& expect) {
    const auto f = dir.path / name;
    std::ofstream(f) << text;
    try {
      load_atmosphere(f);
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(name), std::string::npos) << m;
      EXPECT_NE(m.find(expect), std::string::npos) << m;
    }
  };
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? t : t.replace(at, from.size(), to);
  };
  refused("g.json", with("\"g\": 0.8", "\"g\": 1.5"), "$.mie.g");
  refused("top.json", with("\"top_radius_km\": 6460", "\"top_radius_km\": 6000"), "$.top_radius_km");
  refused("key.json", with("\"ground_albedo\"", "\"ground_albedoo\""), "ground_albedoo");
  refused("ray.json", with("[0.005802, 0.013558, 0.0331]", "[0.005802, 0.013558]"), "$.rayleigh.scattering");
  refused("truncated.json", good.substr(0, good.size() / 2), "truncated.json");
  EXPECT_NO_THROW(load_atmosphere(default_atmosphere_file()));
}

}  // namespace
