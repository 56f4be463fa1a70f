#pragma once
// Helpers shared by the scene tests: a private temporary folder per test, and error-message checks.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <string>

#include "engine/core/error.h"
#include "engine/core/json.h"
#include "engine/ecs/serialize.h"
#include "engine/scene/serialization.h"
#include "tests/support/temp_dir.h"

namespace cumulo::scene::test {

// A fresh folder named after the running test (CTest runs tests in parallel processes).
inline std::filesystem::path temp_dir() {
  return cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_scene"));
}

// Runs `fn`, expects a cumulo::Error whose message contains every one of `parts`; returns the message.
inline std::string expect_error(const std::function<void()>& fn, std::initializer_list<std::string> parts) {
  try {
    fn();
  } catch (const Error& e) {
    std::string msg = e.what();
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing \"" << p << "\" in: " << msg;
    return msg;
  }
  ADD_FAILURE() << "expected a cumulo::Error";
  return {};
}

// The sample level also names module components (the clouds module's Cloudscape, WeatherScheduler,
// StormbirdDissipation, Trigger, OrographicClouds, WeatherZone and CloudGrowth).
// The engine's tests must not link modules, so they accept those as opaque JSON (one stand-in type per
// component name); the module's own tests check them.
template <int Tag>
struct ModuleComponentStandIn {
  Json value;
};
template <int Tag>
inline void register_stand_in(ecs::ComponentRegistry& reg, const char* name) {
  using T = ModuleComponentStandIn<Tag>;
  reg.register_component<T>(name, [](const T& c) { return c.value; }, [](const JsonView& v) { return T{v.raw()}; });
}
inline void register_sample_level_components(ecs::ComponentRegistry& reg) {
  register_components(reg);
  register_stand_in<0>(reg, "Cloudscape");
  register_stand_in<1>(reg, "WeatherScheduler");
  register_stand_in<2>(reg, "StormbirdDissipation");
  register_stand_in<3>(reg, "Trigger");
  register_stand_in<4>(reg, "OrographicClouds");
  register_stand_in<5>(reg, "WeatherZone");
  register_stand_in<6>(reg, "CloudGrowth");
}

}  // namespace cumulo::scene::test
