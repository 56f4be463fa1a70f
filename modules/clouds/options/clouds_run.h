#pragma once
// What the clouds' run commands (`cumulo bench`, `cumulo reference`, `cumulo fidelity`) get from the module
// that registers them (CloudsModule::register_run_commands): the renderer they configure and measure, the
// clouds' flags, and every module of the build, with which their headless session
// (engine/app/headless_session.h) runs the level, as `cumulo run` does.
#include <functional>

#include "engine/app/module.h"
#include "modules/clouds/render/cloud_feature.h"

namespace cumulo {
class ArgParser;
}

namespace cumulo::clouds {

struct CloudsRun {
  render::CloudFeature& feature;
  std::function<void(ArgParser&)> add_run_options;  // the clouds' `cumulo run` flags (options/cloud_options.h)
  app::Modules modules;
};

}  // namespace cumulo::clouds
