#pragma once
// What a viewer sees in a cloud, measured on a real-time image and on the reference alike (issue 21): the
// belly's brightness (no black bellies), the silver lining's rim over core ratio, and the band-pass
// contrast that says whether the inside of a cloud has structure or is a flat haze. Each measure is taken
// on the reference's silhouette (its view-ray opacity) so both images are judged over the same pixels,
// and the reference's own noise is taken out where it would count as contrast.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/reference/reference_tracer.h"

namespace cumulo::clouds {

// Per-pixel luminance of an image, and of a reference's radiance.
std::vector<float> luminance_image(const std::vector<glm::vec4>& rgba);

// The largest 4-connected region of the reference with opacity >= `opacity` (the largest cloud), as a mask.
std::vector<uint8_t> largest_silhouette(const render::ReferenceImage& ref, float opacity = 0.5f);

// Mean luminance over the lower third (image rows) of `mask`; NaN where the mask is empty.
double lower_third_mean(const std::vector<float>& lum, const std::vector<uint8_t>& mask, uint32_t width, uint32_t height);

// Each mask pixel's 4-connected distance (pixels) to the nearest pixel outside the mask (1 at the edge);
// 0 outside. The image's border counts as outside only when `border_outside`.
std::vector<uint16_t> inside_distance(const std::vector<uint8_t>& mask, uint32_t width, uint32_t height, bool border_outside);

// The silver lining: mean luminance of the mask's outermost `rim_px` pixels over that of its core (`core_px`
// in and further). NaN where either is empty.
double rim_core_ratio(const std::vector<float>& lum, const std::vector<uint8_t>& mask, uint32_t width, uint32_t height,
                      uint16_t rim_px = 2, uint16_t core_px = 5);

// Band-pass contrast: mean |G(L, 1.5 px) - G(L, 8 px)| / mean(L) over the image. With a per-pixel standard
// error (`stderr_lum`, not empty), the noise is taken out pixel by pixel: the band-pass of independent noise
// has variance sum_k w_k^2 se_k^2 (w the difference of the two kernels), and each pixel contributes
// sqrt(max(0, bp^2 - var)) instead of |bp|.
double band_pass_contrast(const std::vector<float>& lum, uint32_t width, uint32_t height, const std::vector<float>& stderr_lum = {});

// The three measures of a view, on the real-time image and the reference (noise taken out of its band-pass).
struct ViewFeatures {
  double belly_realtime = 0, belly_reference = 0;      // lower_third_mean on the largest silhouette (opacity >= 0.5)
  double rim_core_realtime = 0, rim_core_reference = 0;  // rim_core_ratio on the largest silhouette (opacity >= 0.2)
  double band_pass_realtime = 0, band_pass_reference = 0;
  // Relative differences, real-time against reference (0.1: 10 % above); NaN where the reference's is 0 or NaN.
  double belly_difference() const { return relative(belly_realtime, belly_reference); }
  double rim_core_difference() const { return relative(rim_core_realtime, rim_core_reference); }
  double band_pass_difference() const { return relative(band_pass_realtime, band_pass_reference); }
  static double relative(double a, double b) { return b > 0.0 ? a / b - 1.0 : std::numeric_limits<double>::quiet_NaN(); }
};
// The reference's side, measured once per view (its silhouettes and its noise-corrected band-pass are the same
// for every real-time image compared with it).
struct ReferenceFeatures {
  std::vector<uint8_t> body, outline;  // largest silhouettes at opacity 0.5 and kCloudOpacity
  double belly = 0, rim_core = 0, band_pass = 0;
};
ReferenceFeatures reference_features(const render::ReferenceImage& reference);
ViewFeatures view_features(const std::vector<glm::vec4>& realtime, const render::ReferenceImage& reference,
                           const ReferenceFeatures& measured);

// Gaussian blur (clamped edges), separable; exposed for the tests.
std::vector<float> gaussian_blur(const std::vector<float>& img, uint32_t width, uint32_t height, float sigma);

}  // namespace cumulo::clouds
