#pragma once
// The named gameplay events the clouds module's triggers and Stormbird dissipation react to are the
// engine's (engine/app/game_events.h: fire_event, `--event NAME@SECONDS`, recorded and replayed by
// `cumulo run --record / --replay`); these names keep the module's gameplay code in one namespace.
#include "engine/app/game_events.h"

namespace cumulo::clouds::gameplay {

using app::add_scripted_events_system;
using app::fire_event;
using app::GameEvent;
using app::parse_scheduled_event;
using app::schedule_event;
using app::ScheduledEvent;
using app::ScheduledEvents;

}  // namespace cumulo::clouds::gameplay
