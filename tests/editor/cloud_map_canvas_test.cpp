#include "editor/model/cloud_map_canvas.h"

#include <gtest/gtest.h>

namespace cumulo::editor {
namespace {

PaintedCloudMap flat(uint32_t w, uint32_t h, uint8_t r, uint8_t g = 128, uint8_t b = 128) {
  PaintedCloudMap m{w, h, {}};
  for (uint32_t i = 0; i < w * h; ++i) m.rgba.insert(m.rgba.end(), {r, g, b, 255});
  return m;
}

uint8_t at(const PaintedCloudMap& m, int x, int y, int c) { return m.rgba[(size_t(y) * m.width + x) * 4 + c]; }

TEST(CloudMapCanvas, ChannelNames) {
  EXPECT_EQ(parse_map_channel("coverage"), MapChannel::Coverage);
  EXPECT_EQ(parse_map_channel("precipitation"), MapChannel::Precipitation);
  EXPECT_EQ(parse_map_channel("type"), MapChannel::Type);
  EXPECT_EQ(parse_map_channel("Coverage"), std::nullopt);
  EXPECT_EQ(parse_map_channel("alpha"), std::nullopt);
  for (MapChannel c : {MapChannel::Coverage, MapChannel::Precipitation, MapChannel::Type})
    EXPECT_EQ(parse_map_channel(map_channel_name(c)), c);
  EXPECT_EQ(map_channel_index(MapChannel::Precipitation), 1);
}

TEST(CloudMapCanvas, DabHasAHardCoreAndASoftEdge) {
  PaintedCloudMap m = flat(64, 64, 255);
  // Radius 0.25 of 64 px = 16 px, centred on pixel (32, 32)'s corner.
  const PaintRect r = paint_dab(m, MapChannel::Coverage, {0.5f, 0.5f}, 0.25f, 0.0f);
  EXPECT_FALSE(r.empty());
  EXPECT_EQ(at(m, 32, 32, 0), 0);      // centre: the target value
  EXPECT_EQ(at(m, 32 + 8, 32, 0), 0);  // inside 60% of the radius: full strength
  const uint8_t edge = at(m, 32 + 13, 32, 0);
  EXPECT_GT(edge, 0);  // the falloff
  EXPECT_LT(edge, 255);
  EXPECT_GT(at(m, 32 + 14, 32, 0), edge);  // monotonic toward the edge
  EXPECT_EQ(at(m, 32 + 17, 32, 0), 255);   // outside
  EXPECT_EQ(at(m, 0, 0, 0), 255);
  // Only the painted channel moves.
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      ASSERT_EQ(at(m, x, y, 1), 128);
      ASSERT_EQ(at(m, x, y, 2), 128);
      ASSERT_EQ(at(m, x, y, 3), 255);
    }
  EXPECT_LE(r.x0, 32 - 13);
  EXPECT_GE(r.x1, 32 + 14);
  EXPECT_EQ(brush_falloff(0.0f), 1.0f);
  EXPECT_EQ(brush_falloff(0.6f), 1.0f);
  EXPECT_EQ(brush_falloff(1.0f), 0.0f);
  EXPECT_NEAR(brush_falloff(0.8f), 0.5f, 1e-6f);
}

TEST(CloudMapCanvas, StrengthMovesPartWay) {
  PaintedCloudMap m = flat(16, 16, 0, 0, 0);
  paint_dab(m, MapChannel::Precipitation, {0.5f, 0.5f}, 0.2f, 1.0f, 0.5f);
  EXPECT_EQ(at(m, 8, 8, 1), 128);  // 0 + (255 - 0) * 0.5, rounded
  paint_dab(m, MapChannel::Precipitation, {0.5f, 0.5f}, 0.2f, 1.0f, 0.5f);
  EXPECT_NEAR(at(m, 8, 8, 1), 191.5, 1.0);  // builds up like an airbrush
  EXPECT_TRUE(paint_dab(m, MapChannel::Precipitation, {0.5f, 0.5f}, 0.2f, 1.0f, 0.0f).empty());
}

TEST(CloudMapCanvas, WrapsAcrossTheEdges) {
  PaintedCloudMap m = flat(32, 32, 255);
  const PaintRect r = paint_dab(m, MapChannel::Coverage, {1.0f, 0.0f}, 0.1f, 0.0f);  // == (0, 0)
  EXPECT_EQ(at(m, 0, 0, 0), 0);
  EXPECT_EQ(at(m, 31, 0, 0), 0);
  EXPECT_EQ(at(m, 0, 31, 0), 0);
  EXPECT_EQ(at(m, 31, 31, 0), 0);
  EXPECT_EQ(at(m, 16, 16, 0), 255);
  EXPECT_LT(r.x0, 0);  // reaches past the left edge, unwrapped
  EXPECT_LT(r.y0, 0);
  // uv outside 0..1 is the same place.
  PaintedCloudMap a = flat(32, 32, 255), b = flat(32, 32, 255);
  paint_dab(a, MapChannel::Type, {0.25f, 0.75f}, 0.1f, 0.2f);
  paint_dab(b, MapChannel::Type, {-0.75f, 1.75f}, 0.1f, 0.2f);
  EXPECT_EQ(a.rgba, b.rgba);
}

TEST(CloudMapCanvas, IsDeterministicAndNeverPaintsAPixelTwice) {
  PaintedCloudMap a = flat(40, 24, 10), b = flat(40, 24, 10);
  for (PaintedCloudMap* m : {&a, &b}) {
    paint_dab(*m, MapChannel::Coverage, {0.3f, 0.6f}, 0.07f, 0.9f, 0.7f);
    paint_dab(*m, MapChannel::Coverage, {0.95f, 0.1f}, 0.2f, 0.4f, 0.3f);
  }
  EXPECT_EQ(a.rgba, b.rgba);
  // A brush as wide as the map: every pixel once, at most half way with strength 0.5.
  PaintedCloudMap big = flat(16, 16, 0);
  paint_dab(big, MapChannel::Coverage, {0.5f, 0.5f}, 1.0f, 1.0f, 0.5f);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) ASSERT_LE(at(big, x, y, 0), 128);
}

TEST(CloudMapCanvas, TinyBrushPaintsThePixelUnderIt) {
  PaintedCloudMap m = flat(8, 8, 255);
  EXPECT_FALSE(paint_dab(m, MapChannel::Coverage, {0.3f, 0.3f}, 0.001f, 0.0f).empty());
  EXPECT_LT(at(m, 2, 2, 0), 255);
}

TEST(CloudMapCanvas, MalformedMapIsLeftAlone) {
  PaintedCloudMap m{4, 4, std::vector<uint8_t>(10, 7)};
  EXPECT_TRUE(paint_dab(m, MapChannel::Coverage, {0.5f, 0.5f}, 0.5f, 0.0f).empty());
  EXPECT_EQ(m.rgba, std::vector<uint8_t>(10, 7));
  PaintedCloudMap ok = flat(4, 4, 9);
  EXPECT_TRUE(paint_dab(ok, MapChannel::Coverage, {0.5f, 0.5f}, 0.0f, 0.0f).empty());
  EXPECT_TRUE(paint_dab(ok, MapChannel::Coverage, {NAN, 0.5f}, 0.5f, 0.0f).empty());
}

}  // namespace
}  // namespace cumulo::editor
