#include "modules/clouds/envelope/envelope_bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "modules/clouds/envelope/envelope_steps.h"
#include "modules/clouds/noise/noise.h"

namespace cumulo::clouds::envelope {
namespace {

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// Full weight to 4/5 of the radius: a region bounds a rule without a hard cut.
float region_weight(const std::optional<EnvelopeRegion>& r, glm::vec2 p) {
  if (!r) return 1.0f;
  return 1.0f - smoothstep(0.8f * r->radius_m, r->radius_m, glm::distance(p, r->center));
}

// One texel's union of everything that covers it: the highest coverage, and heights and detail type weighted by
// each contribution's coverage, so where a rule fades out its heights fade with it (a minimum and a maximum would jump
// to a rule's heights where its coverage starts, standing a wall of cloud on the texel where two rules meet).
struct Union {
  float coverage = 0.0f, bottom_sum = 0.0f, top_sum = 0.0f, detail_sum = 0.0f, weight = 0.0f;
  float bottom = 0.0f, top = 0.0f;  // resolve()'s
  void add(float c, float b, float t, float detail) {
    if (!(c > 0.0f) || !(t - b >= kMinThicknessM)) return;
    coverage = std::max(coverage, c);
    bottom_sum += c * b;
    top_sum += c * t;
    detail_sum += c * detail;
    weight += c;
  }
  void resolve() {
    if (!(weight > 0.0f)) return;
    bottom = bottom_sum / weight;
    top = top_sum / weight;
  }
};

// The terrain at the texel centres; its gradient (central differences half a texel apart) when a bank needs it.
struct TerrainSamples {
  std::vector<float> height;
  std::vector<glm::vec2> gradient;
  glm::vec2 peak{0.0f};
};

TerrainSamples sample_terrain(const OrographicClouds& spec, const EnvelopeMaps& m, const HeightField& terrain) {
  const uint32_t n = m.resolution;
  const bool banks = std::any_of(spec.rules.begin(), spec.rules.end(),
                                 [](const EnvelopeRule& r) { return r.type() == RuleType::Bank; });
  TerrainSamples t;
  t.height.resize(size_t(n) * n);
  if (banks) t.gradient.resize(size_t(n) * n);
  float peak = -std::numeric_limits<float>::infinity();
  // The slope a bank reads is the terrain's over kBankSlopeSpanM: at a texel's scale the ground's roughness turned the
  // bank's weight on and off from one texel to the next, standing columns of cloud on the slopes.
  const float e = std::max(0.5f * m.texel_m, 0.5f * kBankSlopeSpanM);
  auto height_at = [&](float x, float z) {
    const float h = terrain(x, z);
    if (!std::isfinite(h))
      fail("%s: the terrain's height at (%g, %g) is not a finite number", spec.where.c_str(), x, z);
    return h;
  };
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const glm::vec2 c = m.origin + (glm::vec2(float(i), float(j)) + 0.5f) * m.texel_m;
      const size_t k = size_t(j) * n + i;
      t.height[k] = height_at(c.x, c.y);
      if (banks) {
        // Of the ground (sea level over water): the sea floor's slopes lift no air.
        auto g = [&](float x, float z) { return std::max(height_at(x, z), 0.0f); };
        t.gradient[k] = glm::vec2(g(c.x + e, c.y) - g(c.x - e, c.y), g(c.x, c.y + e) - g(c.x, c.y - e)) / (2.0f * e);
      }
      const bool inside = c.x <= spec.extent_max.x && c.y <= spec.extent_max.y;
      if (inside && t.height[k] > peak) {
        peak = t.height[k];
        t.peak = c;
      }
    }
  return t;
}

// The rule's roughness at p: a 2D fBm (about -1..1, mostly within +-0.5) of features variation_m across, its own per
// rule; 0 without variation.
float roughness(const EnvelopeRule& r, size_t index, glm::vec2 p) {
  if (!(r.variation > 0.0f)) return 0.0f;
  const glm::vec3 q(p.x / r.variation_m, p.y / r.variation_m, 0.5f);
  return perlin_fbm(q, 4096, 3, derive_seed(0xe1e0u, uint32_t(index)));
}

// Adds the rule with its roughness: the top moves by up to `variation` of the thickness and the coverage thins where
// the top comes down (a painted NDF's lumps and gaps, which the 3D noise then erodes).
void add_rough(const EnvelopeRule& r, float rough, float c, float bottom, float top, Union& u) {
  const float thickness = std::max(top - bottom, 0.0f);
  const float v = r.variation * rough;
  const float t = bottom + std::max(thickness * (1.0f + 1.5f * v), std::min(thickness, kMinThicknessM));
  u.add(c * std::clamp(1.0f + 2.0f * v, 0.0f, 1.0f), bottom, t, r.detail_type);
}

void add_rule(const EnvelopeRule& r, size_t index, float global_coverage, glm::vec2 p, float terrain, glm::vec2 gradient,
              glm::vec2 peak, Union& u) {
  const float ground = std::max(terrain, 0.0f);
  const float c = r.coverage * global_coverage;
  if (const auto* cap = std::get_if<CapRule>(&r.kind)) {
    const float d = glm::distance(p, cap->at_peak ? peak : cap->center);
    if (d >= cap->radius_m) return;
    // A dome: the top comes down toward the side (to 60 % of the thickness at the radius), as a cap cloud's does.
    const float f = d / cap->radius_m;
    const float top = cap->base_m + (cap->top_m - cap->base_m) * (0.6f + 0.4f * std::sqrt(std::max(1.0f - f * f, 0.0f)));
    add_rough(r, roughness(r, index, p), c * (1.0f - smoothstep(0.5f * cap->radius_m, cap->radius_m, d)), cap->base_m,
              top, u);
  } else if (const auto* bank = std::get_if<BankRule>(&r.kind)) {
    const glm::vec2 downwind = -glm::normalize(glm::vec2(bank->wind_from.x, bank->wind_from.z));
    const float lo = bank->terrain_m.x, hi = bank->terrain_m.y, band = 0.25f * (hi - lo);
    const float w = smoothstep(0.0f, kBankFullSlope, glm::dot(gradient, downwind)) * smoothstep(lo, lo + band, ground) *
                    (1.0f - smoothstep(hi - band, hi, ground)) * region_weight(r.region, p);
    const float bottom = ground + bank->base_above_terrain_m;
    add_rough(r, roughness(r, index, p), c * w, bottom, bottom + bank->thickness_m, u);
  } else if (const auto* layer = std::get_if<LayerRule>(&r.kind)) {
    const float w = (1.0f - smoothstep(layer->below_terrain_m - kLayerFadeM, layer->below_terrain_m, terrain)) *
                    region_weight(r.region, p);
    add_rough(r, roughness(r, index, p), c * w, ground + layer->base_above_terrain_m, layer->top_m, u);
  }
}

void add_painted(const PaintedMaps& painted, const PaintedMapSet& set, const OrographicClouds& spec, glm::vec2 p,
                 float terrain, Union& u) {
  const glm::vec2 uv = (p - spec.extent_min) / (spec.extent_max - spec.extent_min);
  if (uv.x > 1.0f || uv.y > 1.0f) return;  // the map's square past the extent's shorter side
  const float base = set.relative_to_terrain ? std::max(terrain, 0.0f) : 0.0f;
  const float span = set.height_range.y - set.height_range.x;
  const float bottom = base + set.height_range.x + painted.bottom.sample(uv) * span;
  const float top = base + set.height_range.x + painted.top.sample(uv) * span;
  const float coverage = painted.coverage.empty() ? 1.0f : painted.coverage.sample(uv);
  const float detail = painted.detail.empty() ? 0.5f : painted.detail.sample(uv);
  u.add(coverage * spec.coverage, bottom, top, detail);
}

}  // namespace

EnvelopeMaps bake_envelope_maps(const OrographicClouds& spec, const HeightField& terrain_height,
                                const HeightField& ceiling, const std::function<void(float)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  auto report = [&](float f) {
    if (progress) progress(f);
  };
  if (!terrain_height) fail("%s: bake_envelope_maps needs the terrain's height", spec.where.c_str());
  const glm::vec2 size = spec.extent_max - spec.extent_min;
  if (!(size.x > 0.0f) || !(size.y > 0.0f) || spec.resolution == 0)
    fail("%s: an empty extent or resolution cannot be baked", spec.where.c_str());
  EnvelopeMaps m;
  m.resolution = spec.resolution;
  m.origin = spec.extent_min;
  m.texel_m = std::max(size.x, size.y) / float(spec.resolution);
  m.edge_width_m = spec.edge_m;
  const uint32_t n = m.resolution;

  PaintedMaps loaded;
  const PaintedMaps* painted = spec.maps ? spec.painted.get() : nullptr;
  if (spec.maps && !painted) {
    loaded = load_painted_maps(*spec.maps, spec.level_dir);
    painted = &loaded;
  }
  const TerrainSamples terrain = sample_terrain(spec, m, terrain_height);
  report(0.2f);

  m.shape.assign(size_t(n) * n, glm::vec4(0.0f, 0.0f, 0.0f, 0.5f));
  size_t footprint = 0;
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const glm::vec2 p = m.origin + (glm::vec2(float(i), float(j)) + 0.5f) * m.texel_m;
      const size_t k = size_t(j) * n + i;
      const float h = terrain.height[k];
      const glm::vec2 gradient = terrain.gradient.empty() ? glm::vec2(0.0f) : terrain.gradient[k];
      Union u;
      if (painted) add_painted(*painted, *spec.maps, spec, p, h, u);
      for (size_t ri = 0; ri < spec.rules.size(); ++ri)
        add_rule(spec.rules[ri], ri, spec.coverage, p, h, gradient, terrain.peak, u);
      u.resolve();
      if (ceiling) {
        const float limit = ceiling(p.x, p.y) - kCeilingGapM;
        if (limit < u.top) u.top = limit;
        if (!(u.top - u.bottom >= kMinThicknessM)) u.coverage = 0.0f;
      }
      if (u.coverage > 0.0f) {
        m.shape[k] = glm::vec4(u.bottom, u.top, std::min(u.coverage, 1.0f), u.detail_sum / u.weight);
        ++footprint;
      }
    }
  report(0.4f);

  derive_envelope_steps(m);
  report(1.0f);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  LOG_INFO("clouds: envelope%s%s: %ux%u texels of %.2f m, footprint %.1f%%, baked in %.0f ms",
           spec.where.empty() ? "" : " ", spec.where.c_str(), n, n, m.texel_m,
           100.0 * double(footprint) / double(size_t(n) * n), ms);
  return m;
}

float envelope_profile(float y, float bottom, float top, float edge_m_here, float edge_width_m, float coverage) {
  if (!(coverage > 0.0f) || !(top > bottom)) return 0.0f;
  const float hf = (y - bottom) / (top - bottom);
  if (!(hf > 0.0f && hf < 1.0f)) return 0.0f;
  const float top_gradient = std::pow(1.0f - hf, 1.5f);
  const float bottom_gradient = hf * hf;
  const float edge_gradient = std::clamp(edge_m_here / std::max(edge_width_m, 1e-3f), 0.0f, 1.0f);
  return bottom_gradient * top_gradient * edge_gradient / kProfilePeak * std::min(coverage, 1.0f);
}

EnvelopeSample sample_envelope(const EnvelopeMaps& m, glm::vec3 world) {
  EnvelopeSample s;
  if (m.empty()) return s;
  const float n = float(m.resolution);
  const glm::vec2 p = (glm::vec2(world.x, world.z) - m.origin) / m.texel_m;
  if (!(p.x >= 0.0f && p.y >= 0.0f && p.x <= n && p.y <= n)) return s;
  const glm::vec2 t = glm::clamp(p - 0.5f, glm::vec2(0.0f), glm::vec2(n - 1.0f));
  const uint32_t i0 = std::min(uint32_t(t.x), m.resolution - 1), j0 = std::min(uint32_t(t.y), m.resolution - 1);
  const uint32_t i1 = std::min(i0 + 1, m.resolution - 1), j1 = std::min(j0 + 1, m.resolution - 1);
  const float fx = t.x - float(i0), fz = t.y - float(j0);
  auto k = [&](uint32_t i, uint32_t j) { return size_t(j) * m.resolution + i; };
  auto mix4 = [&](const std::vector<glm::vec4>& v) {
    return glm::mix(glm::mix(v[k(i0, j0)], v[k(i1, j0)], fx), glm::mix(v[k(i0, j1)], v[k(i1, j1)], fx), fz);
  };
  auto mix1 = [&](const std::vector<float>& v) {
    const float a = v[k(i0, j0)] + (v[k(i1, j0)] - v[k(i0, j0)]) * fx;
    const float b = v[k(i0, j1)] + (v[k(i1, j1)] - v[k(i0, j1)]) * fx;
    return a + (b - a) * fz;
  };
  s.shape = mix4(m.shape);
  s.edge_m = mix1(m.edge_m);
  s.height_fraction = std::clamp((world.y - s.shape.x) / std::max(s.shape.y - s.shape.x, 1e-3f), 0.0f, 1.0f);
  s.edge_gradient = std::clamp(s.edge_m / std::max(m.edge_width_m, 1e-3f), 0.0f, 1.0f);
  s.profile = envelope_profile(world.y, s.shape.x, s.shape.y, s.edge_m, m.edge_width_m, s.shape.z);
  return s;
}

}  // namespace cumulo::clouds::envelope
