// Parameters of the atmosphere's LUT passes and the sky pass (engine/render/atmosphere), shared by C++
// and GLSL: the preset (render::AtmosphereParams) in GPU form plus the lights and the viewer.
#ifndef CUMULO_SHARED_ATMOSPHERE_PARAMS_H
#define CUMULO_SHARED_ATMOSPHERE_PARAMS_H
#include "shared/common.h"

#define ATMOSPHERE_PARAMS_BINDING 0       // uniform AtmosphereGpuParams (LUT passes; the sky pass: binding 2)
#define ATMOSPHERE_TRANSMITTANCE_BINDING 1  // sampler2D transmittance LUT (ms, sky view, sky)
#define ATMOSPHERE_MS_BINDING 2           // sampler2D psi_ms LUT (sky view)
#define ATMOSPHERE_OUT_BINDING 3          // image2D rgba16f written by a LUT pass
#define SKY_ATMOSPHERE_PARAMS_BINDING 1   // sky pass: uniform AtmosphereGpuParams
#define SKY_VIEW_BINDING 2                // sky pass: sampler2D sky-view LUT
#define SKY_TRANSMITTANCE_BINDING 3       // sky pass: sampler2D transmittance LUT

#define ATMOSPHERE_TRANSMITTANCE_W 256
#define ATMOSPHERE_TRANSMITTANCE_H 64
#define ATMOSPHERE_MS_SIZE 32
#define ATMOSPHERE_SKY_VIEW_W 192
#define ATMOSPHERE_SKY_VIEW_H 108
// Aerial perspective (Hillaire 2020 section 5.4): a camera froxel volume, 32x32 over the screen, 32 slices
// along the view ray to ATMOSPHERE_AERIAL_KM, slice k ending at (k + 1)^2 / 32^2 of it (dense near the
// viewer, where the terrain is); rgb in-scattered radiance from the camera to the slice's end, a the
// mean transmittance.
#define ATMOSPHERE_AERIAL_SIZE 32
#define ATMOSPHERE_AERIAL_KM 32.0

CUMULO_SHARED_BEGIN

struct AtmosphereGpuParams {
  vec4 radii;     // x: bottom radius (km), y: top radius (km), z: Rayleigh scale height (km), w: Mie scale height (km)
  vec4 rayleigh;  // rgb: Rayleigh scattering (1/km); w: Mie g
  vec4 mie;       // x: Mie scattering, y: Mie extinction (1/km), z: ozone centre (km), w: ozone width (km)
  vec4 ozone;     // rgb: ozone absorption (1/km); w: airglow (radiance x (1, 1.2, 2): night is never black)
  vec4 albedo;    // rgb: ground albedo; w: solar irradiance (renderer units)
  vec4 sun;       // xyz: toward the sun (world); w: its irradiance scale (1)
  vec4 moon;      // xyz: toward the moon; w: its irradiance scale (0 by day)
  vec4 view;      // x: camera altitude (km); y: sun angular radius (rad); z, w: unused
};
CUMULO_SHARED_SIZE(AtmosphereGpuParams, 128)

// Push constants of atmosphere_aerial.comp.
struct AtmosphereAerialPush {
  mat4 inv_view_proj;  // clip -> world (the camera's rays)
  vec4 camera;         // xyz: world position (m); w unused
};
CUMULO_SHARED_SIZE(AtmosphereAerialPush, 80)

CUMULO_SHARED_END

#endif
