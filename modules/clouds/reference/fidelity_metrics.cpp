#include "modules/clouds/reference/fidelity_metrics.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"

namespace cumulo::clouds {

namespace {
double floor_luminance(const render::ReferenceImage& ref, float fraction) {
  double sum = 0;
  for (const glm::vec4& v : ref.radiance) sum += luminance(glm::vec3(v));
  return std::max(1e-6, fraction * sum / double(std::max<size_t>(1, ref.radiance.size())));
}
void check_sizes(const std::vector<glm::vec4>& rt, const render::ReferenceImage& ref) {
  if (rt.size() != ref.radiance.size() || rt.empty())
    fail("fidelity: the real-time image has %zu pixels, the reference %zu", rt.size(), ref.radiance.size());
}
}  // namespace

FidelityError fidelity_error(const std::vector<glm::vec4>& rt, const render::ReferenceImage& ref, float floor_fraction) {
  check_sizes(rt, ref);
  const double floor = floor_luminance(ref, floor_fraction);
  FidelityError e;
  double all = 0;
  for (size_t i = 0; i < rt.size(); ++i) {
    const double lr = luminance(glm::vec3(ref.radiance[i])), lt = luminance(glm::vec3(rt[i]));
    const double denom = std::max(lr, floor);
    const double err = std::fabs(lt - lr) / denom;
    all += err;
    if (ref.radiance[i].a >= kCloudOpacity) {
      e.error_in_cloud += err;
      e.realtime_luminance_in_cloud += lt;
      e.reference_luminance_in_cloud += lr;
      e.bias_in_cloud += (lt - lr) / denom;
      const double se = ref.luminance_stderr.empty() ? 0.0 : ref.luminance_stderr[i];
      const double rel_se = se / denom;
      const double corrected = std::sqrt(std::max(0.0, (lt - lr) * (lt - lr) - se * se)) / denom;
      e.error_in_cloud_corrected += corrected;
      if (ref.radiance[i].a >= kOpaqueOpacity) {
        e.error_opaque_corrected += corrected;
        e.bias_opaque += (lt - lr) / denom;
        ++e.opaque_pixels;
      }
      e.stderr_in_cloud += rel_se;
      e.noise_in_cloud += std::sqrt(2.0 / 3.14159265358979) * rel_se;
      ++e.cloud_pixels;
    }
  }
  e.error_mean = all / double(rt.size());
  if (e.cloud_pixels) {
    const double n = double(e.cloud_pixels);
    e.realtime_luminance_in_cloud /= n, e.reference_luminance_in_cloud /= n;
    e.error_in_cloud /= n, e.error_in_cloud_corrected /= n, e.bias_in_cloud /= n, e.noise_in_cloud /= n, e.stderr_in_cloud /= n;
  }
  if (e.opaque_pixels) e.error_opaque_corrected /= double(e.opaque_pixels), e.bias_opaque /= double(e.opaque_pixels);
  return e;
}

gpu::Rgba8Image error_map(const std::vector<glm::vec4>& rt, const render::ReferenceImage& ref, float floor_fraction) {
  check_sizes(rt, ref);
  const double floor = floor_luminance(ref, floor_fraction);
  gpu::Rgba8Image img;
  img.width = ref.width, img.height = ref.height;
  img.pixels.resize(rt.size() * 4);
  // Stops of the ramp at 0, 5, 10, 15, 30 %.
  const float stops[5] = {0.0f, 0.05f, 0.10f, 0.15f, 0.30f};
  const glm::vec3 colours[5] = {{0, 0, 0}, {0.1f, 0.3f, 1.0f}, {0.1f, 0.9f, 0.2f}, {1.0f, 0.9f, 0.1f}, {1.0f, 0.1f, 0.05f}};
  double mean = 0;
  for (const glm::vec4& v : ref.radiance) mean += luminance(glm::vec3(v));
  mean = std::max(1e-6, mean / double(rt.size()));
  for (size_t i = 0; i < rt.size(); ++i) {
    const double lr = luminance(glm::vec3(ref.radiance[i])), lt = luminance(glm::vec3(rt[i]));
    const float err = float(std::fabs(lt - lr) / std::max(lr, floor));
    glm::vec3 c;
    if (ref.radiance[i].a >= kCloudOpacity) {
      int k = 0;
      while (k < 3 && err > stops[k + 1]) ++k;
      const float f = std::clamp((err - stops[k]) / (stops[k + 1] - stops[k]), 0.0f, 1.0f);
      c = glm::mix(colours[k], colours[k + 1], f);
    } else {
      const float g = float(0.35 * lr / (lr + mean));  // the scene, dim, outside the cloud
      c = glm::vec3(g);
    }
    for (int k = 0; k < 3; ++k) img.pixels[i * 4 + size_t(k)] = uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    img.pixels[i * 4 + 3] = 255;
  }
  return img;
}

gpu::Rgba8Image side_by_side(const std::vector<const gpu::Rgba8Image*>& images) {
  gpu::Rgba8Image out;
  if (images.empty()) return out;
  const uint32_t gap = 2;
  out.height = images[0]->height;
  for (const gpu::Rgba8Image* i : images) {
    if (i->height != out.height) fail("side_by_side: images of heights %u and %u", out.height, i->height);
    out.width += i->width + (out.width ? gap : 0);
  }
  out.pixels.assign(size_t(out.width) * out.height * 4, 0);
  for (size_t p = 3; p < out.pixels.size(); p += 4) out.pixels[p] = 255;
  uint32_t x0 = 0;
  for (const gpu::Rgba8Image* i : images) {
    for (uint32_t y = 0; y < i->height; ++y)
      std::copy_n(&i->pixels[size_t(y) * i->width * 4], size_t(i->width) * 4, &out.pixels[(size_t(y) * out.width + x0) * 4]);
    x0 += i->width + gap;
  }
  return out;
}

}  // namespace cumulo::clouds
