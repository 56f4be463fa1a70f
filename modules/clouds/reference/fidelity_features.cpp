#include "modules/clouds/reference/fidelity_features.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "modules/clouds/reference/fidelity_metrics.h"

namespace cumulo::clouds {

std::vector<float> luminance_image(const std::vector<glm::vec4>& rgba) {
  std::vector<float> out(rgba.size());
  for (size_t i = 0; i < rgba.size(); ++i) out[i] = luminance(glm::vec3(rgba[i]));
  return out;
}

std::vector<uint8_t> largest_silhouette(const render::ReferenceImage& ref, float opacity) {
  const uint32_t w = ref.width, h = ref.height;
  std::vector<int32_t> label(size_t(w) * h, -1);
  int32_t best = -1;
  size_t best_size = 0;
  int32_t next = 0;
  std::vector<uint32_t> stack;
  for (uint32_t start = 0; start < w * h; ++start) {
    if (label[start] >= 0 || ref.radiance[start].a < opacity) continue;
    size_t size = 0;
    stack.assign(1, start);
    label[start] = next;
    while (!stack.empty()) {
      const uint32_t p = stack.back();
      stack.pop_back();
      ++size;
      const uint32_t x = p % w, y = p / w;
      const uint32_t nb[4] = {x > 0 ? p - 1 : p, x + 1 < w ? p + 1 : p, y > 0 ? p - w : p, y + 1 < h ? p + w : p};
      for (uint32_t q : nb)
        if (label[q] < 0 && ref.radiance[q].a >= opacity) label[q] = next, stack.push_back(q);
    }
    if (size > best_size) best_size = size, best = next;
    ++next;
  }
  std::vector<uint8_t> mask(label.size(), 0);
  for (size_t i = 0; i < label.size(); ++i) mask[i] = label[i] == best && best >= 0 ? 1 : 0;
  return mask;
}

double lower_third_mean(const std::vector<float>& lum, const std::vector<uint8_t>& mask, uint32_t w, uint32_t h) {
  uint32_t top = h, bottom = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      if (mask[size_t(y) * w + x]) top = std::min(top, y), bottom = std::max(bottom, y);
  if (top > bottom) return std::numeric_limits<double>::quiet_NaN();
  // Image rows grow downward: the lower third begins two thirds of the way from the top row to the bottom.
  const double from = top + (2.0 / 3.0) * double(bottom - top);
  double sum = 0;
  size_t n = 0;
  for (uint32_t y = 0; y < h; ++y)
    if (double(y) >= from)
      for (uint32_t x = 0; x < w; ++x)
        if (mask[size_t(y) * w + x]) sum += lum[size_t(y) * w + x], ++n;
  return n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
}

std::vector<uint16_t> inside_distance(const std::vector<uint8_t>& mask, uint32_t w, uint32_t h, bool border_outside) {
  std::vector<uint16_t> d(mask.size(), 0);
  std::deque<uint32_t> queue;
  const uint16_t far = std::numeric_limits<uint16_t>::max();
  for (uint32_t p = 0; p < w * h; ++p) {
    if (!mask[p]) continue;
    const uint32_t x = p % w, y = p / w;
    bool edge = false;
    auto outside = [&](int64_t xx, int64_t yy) {
      if (xx < 0 || yy < 0 || xx >= int64_t(w) || yy >= int64_t(h)) return border_outside;
      return mask[size_t(yy) * w + size_t(xx)] == 0;
    };
    edge = outside(int64_t(x) - 1, y) || outside(int64_t(x) + 1, y) || outside(x, int64_t(y) - 1) || outside(x, int64_t(y) + 1);
    d[p] = edge ? 1 : far;
    if (edge) queue.push_back(p);
  }
  while (!queue.empty()) {
    const uint32_t p = queue.front();
    queue.pop_front();
    const uint32_t x = p % w, y = p / w;
    const uint32_t nb[4] = {x > 0 ? p - 1 : p, x + 1 < w ? p + 1 : p, y > 0 ? p - w : p, y + 1 < h ? p + w : p};
    for (uint32_t q : nb)
      if (mask[q] && d[q] > d[p] + 1) d[q] = uint16_t(d[p] + 1), queue.push_back(q);
  }
  for (uint16_t& v : d)
    if (v == far) v = 0;  // a mask with no edge at all (the whole image, border inside): no distance
  return d;
}

double rim_core_ratio(const std::vector<float>& lum, const std::vector<uint8_t>& mask, uint32_t w, uint32_t h, uint16_t rim_px,
                      uint16_t core_px) {
  const std::vector<uint16_t> d = inside_distance(mask, w, h, false);
  double rim = 0, core = 0;
  size_t nr = 0, nc = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (d[i] == 0) continue;
    if (d[i] <= rim_px) rim += lum[i], ++nr;
    if (d[i] >= core_px) core += lum[i], ++nc;
  }
  if (!nr || !nc || core <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (rim / double(nr)) / (core / double(nc));
}

namespace {
std::vector<float> kernel(float sigma) {
  const int r = std::max(1, int(std::ceil(3.0f * sigma)));
  std::vector<float> k(size_t(2 * r + 1));
  float s = 0;
  for (int i = -r; i <= r; ++i) s += k[size_t(i + r)] = std::exp(-0.5f * float(i * i) / (sigma * sigma));
  for (float& v : k) v /= s;
  return k;
}
// One separable pass along x (dx 1) or y.
std::vector<float> blur_axis(const std::vector<float>& img, uint32_t w, uint32_t h, const std::vector<float>& k, bool along_x) {
  const int r = int(k.size() / 2);
  std::vector<float> out(img.size(), 0.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) {
        const int64_t xx = along_x ? std::clamp<int64_t>(int64_t(x) + i, 0, w - 1) : x;
        const int64_t yy = along_x ? y : std::clamp<int64_t>(int64_t(y) + i, 0, h - 1);
        s += k[size_t(i + r)] * img[size_t(yy) * w + size_t(xx)];
      }
      out[size_t(y) * w + x] = s;
    }
  return out;
}
}  // namespace

std::vector<float> gaussian_blur(const std::vector<float>& img, uint32_t w, uint32_t h, float sigma) {
  const std::vector<float> k = kernel(sigma);
  return blur_axis(blur_axis(img, w, h, k, true), w, h, k, false);
}

double band_pass_contrast(const std::vector<float>& lum, uint32_t w, uint32_t h, const std::vector<float>& se) {
  const std::vector<float> a = gaussian_blur(lum, w, h, 1.5f), b = gaussian_blur(lum, w, h, 8.0f);
  double mean = 0;
  for (float v : lum) mean += v;
  mean /= double(std::max<size_t>(1, lum.size()));
  if (mean <= 0.0) return 0.0;
  // The band-pass kernel's weights (a difference of two separable Gaussians) at offset (i, j): the noise
  // variance it passes, with clamped edges ignored (they only move the border pixels).
  std::vector<double> var(lum.size(), 0.0);
  if (!se.empty()) {
    const std::vector<float> k1 = kernel(1.5f), k8 = kernel(8.0f);
    const int r1 = int(k1.size() / 2), r8 = int(k8.size() / 2);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        double v = 0;
        for (int j = -r8; j <= r8; ++j)
          for (int i = -r8; i <= r8; ++i) {
            const int64_t xx = std::clamp<int64_t>(int64_t(x) + i, 0, w - 1), yy = std::clamp<int64_t>(int64_t(y) + j, 0, h - 1);
            const double w1 = (std::abs(i) <= r1 && std::abs(j) <= r1) ? double(k1[size_t(i + r1)]) * k1[size_t(j + r1)] : 0.0;
            const double wk = w1 - double(k8[size_t(i + r8)]) * k8[size_t(j + r8)];
            const double s = se[size_t(yy) * w + size_t(xx)];
            v += wk * wk * s * s;
          }
        var[size_t(y) * w + x] = v;
      }
  }
  double sum = 0;
  for (size_t i = 0; i < lum.size(); ++i) {
    const double bp = double(a[i]) - double(b[i]);
    sum += se.empty() ? std::fabs(bp) : std::sqrt(std::max(0.0, bp * bp - var[i]));
  }
  return sum / double(lum.size()) / mean;
}

ReferenceFeatures reference_features(const render::ReferenceImage& ref) {
  const uint32_t w = ref.width, h = ref.height;
  const std::vector<float> lr = luminance_image(ref.radiance);
  ReferenceFeatures f;
  f.body = largest_silhouette(ref, 0.5f);
  f.outline = largest_silhouette(ref, kCloudOpacity);
  f.belly = lower_third_mean(lr, f.body, w, h);
  f.rim_core = rim_core_ratio(lr, f.outline, w, h);
  f.band_pass = band_pass_contrast(lr, w, h, ref.luminance_stderr);
  return f;
}

ViewFeatures view_features(const std::vector<glm::vec4>& rt, const render::ReferenceImage& ref, const ReferenceFeatures& m) {
  const uint32_t w = ref.width, h = ref.height;
  const std::vector<float> lt = luminance_image(rt);
  ViewFeatures f;
  f.belly_realtime = lower_third_mean(lt, m.body, w, h);
  f.belly_reference = m.belly;
  f.rim_core_realtime = rim_core_ratio(lt, m.outline, w, h);
  f.rim_core_reference = m.rim_core;
  f.band_pass_realtime = band_pass_contrast(lt, w, h);
  f.band_pass_reference = m.band_pass;
  return f;
}

}  // namespace cumulo::clouds
