#pragma once
// The clouds module's `cumulo run` flags, in one place and parsed once (by ArgParser: choices from the
// enums' name tables, numbers with their ranges) into the structs of their owners: the renderer's
// (render::CloudRenderOptions) and the simulation's (CloudSimulationOptions). `cumulo bench` and
// `cumulo fidelity` take the same flags.
//
//   --clouds on|off            off: the same frame without the module's passes
//   --cloud-debug VIEW         none | profile | steps | light-grid | split
//   --cloud-formats SET        compressed | uncompressed (default: by device type)
//   --cloud-ablation A         base | voxel-lighting | full (the talk's cost table; default full)
//   --cloud-temporal on|off    temporal accumulation of the jittered march (default on)
//   --cloud-reprojection N     1 of N pixels per frame of the full-resolution march with temporal on: 1 (every
//                              pixel, the 2023 talk), 4, 16 (the 2015 talk), auto (default: 4 at 30 Hz, 16 for
//                              the 40/60 Hz far segment)
//   --cloud-light-grid talk|device   the talk's 256x256x32 light grid, or one sized for the device
//                              (default: 96x96x16 on CPU devices, the talk's elsewhere)
//   --cloud-shadows, --cloud-terrain-shadow, --cloud-light-shafts, --cloud-rain  on|off (default on)
//   --cloud-effects-off LIST   lighting effects of the talks switched off in the march (cumulo fidelity measures each)
//   --cloud-lighting talk|tuned|diffusion|slab  the lighting model (default slab), and its constants' overrides
//   --cloud-sky auto|on|off    the weather-driven 2.5D sky beyond and above the voxel cloudscape
//                              (sky_layer.h; auto, the default: on when the level has a WeatherScheduler)
//   --cloud-sky-occlusion on|off  the 2.5D sky left unmarched where the voxel clouds hide it (default on)
//   --weather ID               the state schedulers start in (drawn every frame without a scheduler)
//   --weather-dir DIR          the folder of weather states (default: the level's)
#include <string>

#include "modules/clouds/render/cloud_render_options.h"

namespace cumulo {
class ArgParser;
}

namespace cumulo::clouds {

struct CloudSimulationOptions {
  std::string weather;      // --weather ID (checked against the weather folder when the level loads)
  std::string weather_dir;  // --weather-dir (empty: the level's weather folder)
};

void add_cloud_run_options(ArgParser& p, render::CloudRenderOptions& render, CloudSimulationOptions& simulation);

}  // namespace cumulo::clouds
