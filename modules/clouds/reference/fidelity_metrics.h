#pragma once
// How far a real-time image is from the path-traced reference (cumulo fidelity): the relative luminance
// error per pixel, |L_rt - L_ref| / max(L_ref, floor), averaged over the image and over the cloud's
// silhouette (the reference's view-ray opacity above a threshold), the part of it that the reference's own
// noise explains, the error with that noise taken out, and a false-colour map of the error.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/color.h"
#include "engine/gpu/readback.h"
#include "modules/clouds/reference/reference_tracer.h"

namespace cumulo::clouds {

struct FidelityError {
  double error_mean = 0.0;      // over every pixel (fraction: 0.15 = 15 %)
  double error_in_cloud = 0.0;  // over the pixels whose reference cloud opacity is >= kCloudOpacity
  double bias_in_cloud = 0.0;   // signed: mean (L_rt - L_ref) / L_ref in cloud (> 0: the real-time image is brighter)
  double noise_in_cloud = 0.0;  // the error the reference's standard error alone gives (E|N(0, se)| / L_ref)
  double stderr_in_cloud = 0.0; // mean relative standard error of the reference in cloud
  // The in-cloud error with the reference's noise taken out, pixel by pixel: E[(L_rt - L_ref)^2] = d^2 + se^2
  // for a true difference d, so each pixel counts sqrt(max(0, (L_rt - L_ref)^2 - se^2)) / L_ref (issue 21's
  // acceptance metric; equal to error_in_cloud when the reference has no standard error).
  double error_in_cloud_corrected = 0.0;
  double realtime_luminance_in_cloud = 0.0, reference_luminance_in_cloud = 0.0;  // means
  uint64_t cloud_pixels = 0;
  // The same noise-corrected error and bias over the opaque pixels only (reference opacity >= kOpaqueOpacity), where
  // the background does not show: the measure of a run with one light alone (--cloud-lights sun|sky), whose
  // background keeps every light in the real-time image and not in the reference.
  double error_opaque_corrected = 0.0, bias_opaque = 0.0;
  uint64_t opaque_pixels = 0;
};
inline constexpr float kCloudOpacity = 0.2f;
inline constexpr float kOpaqueOpacity = 0.99f;

// Pixels with reference luminance below `floor_fraction` x the image's mean count as that floor (a black
// pixel would make any error infinite).
FidelityError fidelity_error(const std::vector<glm::vec4>& realtime, const render::ReferenceImage& reference,
                             float floor_fraction = 0.02f);
// The error as colour: black 0 .. blue 5 % .. green 10 % .. yellow 15 % .. red >= 30 %; outside the cloud
// the reference's luminance in grey, dimmed, so the silhouette reads.
gpu::Rgba8Image error_map(const std::vector<glm::vec4>& realtime, const render::ReferenceImage& reference,
                          float floor_fraction = 0.02f);
// Images side by side, left to right (same height), with a 2-pixel black gap.
gpu::Rgba8Image side_by_side(const std::vector<const gpu::Rgba8Image*>& images);

}  // namespace cumulo::clouds
