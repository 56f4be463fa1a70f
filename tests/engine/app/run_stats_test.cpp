#include "engine/app/run_stats.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace cumulo::app;

TEST(RunStats, JsonHasPerPassMeanMinMaxInFrameOrder) {
  RunStats s;
  s.add_gpu_frame({{"geometry", 2.0}, {"sky", 1.0}, {"tonemap", 0.5}});
  s.add_gpu_frame({{"geometry", 4.0}, {"sky", 3.0}, {"tonemap", 0.5}});
  s.add_cpu_frame_ms(10);
  s.add_cpu_frame_ms(30);
  s.set_frames(2);
  RunStats::Info info;
  info.width = 320;
  info.height = 180;
  info.mode_hz = 30;
  info.device_name = "llvmpipe";
  info.peak_gpu_memory_bytes = 1234;
  // Without validation the error count is unknown, never a reassuring 0.
  auto off = nlohmann::ordered_json::parse(s.to_json(info));
  EXPECT_EQ(off["validation_enabled"], false);
  EXPECT_TRUE(off["validation_errors"].is_null());
  info.validation_enabled = true;
  info.validation_errors = 2;
  auto j = nlohmann::ordered_json::parse(s.to_json(info));
  EXPECT_EQ(j["frames"], 2);
  EXPECT_EQ(j["size"][0], 320);
  EXPECT_EQ(j["validation_enabled"], true);
  EXPECT_EQ(j["validation_errors"], 2);
  EXPECT_EQ(j["peak_gpu_memory_bytes"], 1234);
  EXPECT_EQ(j["device"]["name"], "llvmpipe");
  EXPECT_DOUBLE_EQ(j["cpu_frame_ms"]["mean"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(j["cpu_frame_ms"]["max"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(j["passes"]["geometry"]["mean_ms"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["passes"]["geometry"]["min_ms"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["passes"]["sky"]["max_ms"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["gpu_frame_ms"]["mean"].get<double>(), 5.5);
  EXPECT_DOUBLE_EQ(j["passes"]["geometry"]["median_ms"].get<double>(), 3.0);
  std::vector<std::string> order;
  for (auto& [k, v] : j["passes"].items()) order.push_back(k);
  EXPECT_EQ(order, (std::vector<std::string>{"geometry", "sky", "tonemap"}));
}

TEST(RunStats, MedianIgnoresAFirstFrameOutlier) {
  MinMaxMean m;
  for (double v : {250.0, 4.0, 3.0, 5.0, 4.0}) m.add(v);
  EXPECT_DOUBLE_EQ(m.median(), 4.0);
  EXPECT_DOUBLE_EQ(m.max, 250.0);
  MinMaxMean even;
  for (double v : {1.0, 2.0, 3.0, 10.0}) even.add(v);
  EXPECT_DOUBLE_EQ(even.median(), 2.5);
  EXPECT_DOUBLE_EQ(MinMaxMean{}.median(), 0.0);
}
