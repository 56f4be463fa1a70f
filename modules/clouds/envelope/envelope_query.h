#pragma once
// The Envelope method's clouds' density at a point on the CPU (issue 24): gameplay asks where the cloud is (is the
// player inside the bank, wing-tip streamers), as scene/density_query.h answers for the voxel clouds. The field the
// march samples, envelope_density.glsl's envelope_sample(p, detail): the talk's profile from the same baked maps
// (bilinear), the yield to voxel cloudscape boxes, the up-rez on the 2.5D sky's noise (trilinear, repeating, mip 0)
// scrolled by the wind, the detail erosion. A test compares the two at many points
// (tests/modules/clouds/render/envelope_layer_test.cpp).
//
//   EnvelopeDensityQuery q = EnvelopeDensityQuery::load(maps, prepare_sky_noise());
//   float d = q.density(look, player_position, sim_time);   // 0 outside the envelope; x the extinction: 1/m
#include <filesystem>
#include <memory>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/envelope/envelope_maps.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds::envelope {

// The up-rez's constants; the renderer's EnvelopeMarchSettings takes its defaults from them.
// The base noise's tile: at 600 m the envelope's outlines were smooth sausages (cloud_shape.py roughness of the
// envelope alone at 640x360: ground 1.24, mixed 1.28, bank 1.08); at 300 m its billows reach the 20-80 m of a
// silhouette's bumps seen from a kilometre (1.40, 1.31, 1.29; the backlit cap from `peak` 1.21 -> 1.17 either way).
inline constexpr float kNoiseTileM = 300.0f;
inline constexpr float kDetailTileM = 80.0f;
inline constexpr float kDetailErosion = 0.6f;  // 0: the talk's up-rez alone
// Not in the talk: its erosion, saturate(noise - (1 - profile)), leaves densities of 0.1-0.3 where the voxel up-rez
// (sharpened by its pow) leaves 0.5-1, so at the voxel clouds' extinction the envelope's clouds were a thin haze.
inline constexpr float kDensityScale = 4.0f;
// The voxel clouds' boxes: the envelope fades out over this distance before one (no cloud drawn twice).
inline constexpr float kYieldFadeM = 60.0f;

// How the envelope is drawn this frame: what the component and the weather set, and the up-rez.
struct EnvelopeLook {
  float density = 1.0f;   // x the density (the component's, times the weather's)
  float coverage = 1.0f;  // x the maps' coverage
  float edge_m = 35.0f;   // the edge gradient's width
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;  // m/s: the noise scrolls (pseudomotion)
  float noise_tile_m = kNoiseTileM, detail_tile_m = kDetailTileM;
  float detail_erosion = kDetailErosion;
  float density_scale = kDensityScale;
  std::vector<std::pair<glm::vec3, glm::vec3>> yield_boxes;  // voxel cloudscapes' world boxes (min, max)
  float yield_fade_m = kYieldFadeM;
};

// The noise's scroll (world metres) after `time` seconds: wrapped at 64 tiles, so float precision holds over hours. The
// one definition the renderer and the query share.
glm::vec3 envelope_scroll(glm::vec3 wind_direction, float wind_speed, float noise_tile_m, double time);

class EnvelopeDensityQuery {
 public:
  // `base_noise`: the 2.5D sky's RGBA8 noise (R Perlin-Worley, G/B/A Worley fBm); `detail_noise`: its RGB Worley fBm.
  EnvelopeDensityQuery(std::shared_ptr<const EnvelopeMaps> maps, Volume base_noise, Volume detail_noise);
  // The noise from prepare_sky_noise()'s folder. Throws cumulo::Error naming a missing or malformed file.
  static EnvelopeDensityQuery load(std::shared_ptr<const EnvelopeMaps> maps, const std::filesystem::path& noise_dir);

  // The up-rezzed density times look.density x look.density_scale (x the clouds' extinction: 1/m), 0 outside the
  // envelope. `detail`: the high-frequency erosion (the march's view samples; its light samples leave it out).
  float density(const EnvelopeLook& look, glm::vec3 world, double time, bool detail = true) const;

 private:
  std::shared_ptr<const EnvelopeMaps> maps_;
  Volume base_, detail_;
};

}  // namespace cumulo::clouds::envelope
