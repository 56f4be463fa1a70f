#pragma once
// Budget modes: the frame rate a run targets. The renderer reads the mode to choose pass variants and
// resolutions (DESIGN.md "Budget modes": e.g. the cloud march as one full-resolution pass at 30 Hz, or
// split at 200 m into a half-resolution near pass and a full-resolution far pass at 40/60 Hz, 2023 talk).
#include <array>
#include <cstdint>
#include <string>

#include "engine/core/enum_names.h"

namespace cumulo::render {

enum class BudgetMode : uint8_t { Hz30 = 30, Hz40 = 40, Hz60 = 60 };

inline int budget_hz(BudgetMode m) { return static_cast<int>(m); }
inline double budget_frame_seconds(BudgetMode m) { return 1.0 / budget_hz(m); }
inline double budget_frame_ms(BudgetMode m) { return 1000.0 / budget_hz(m); }

// The flag's spellings; reports print budget_mode_name's "30 Hz".
inline constexpr std::array kBudgetModeFlagNames{EnumName<BudgetMode>{BudgetMode::Hz30, "30"},
                                                 EnumName<BudgetMode>{BudgetMode::Hz40, "40"},
                                                 EnumName<BudgetMode>{BudgetMode::Hz60, "60"}};
// "30", "40" or "60" (also "30hz"); throws cumulo::Error naming the accepted values otherwise.
BudgetMode parse_budget_mode(const std::string& text);
inline const char* budget_mode_name(BudgetMode m) {
  constexpr std::array kNames{EnumName<BudgetMode>{BudgetMode::Hz30, "30 Hz"}, EnumName<BudgetMode>{BudgetMode::Hz40, "40 Hz"},
                              EnumName<BudgetMode>{BudgetMode::Hz60, "60 Hz"}};
  return name_of(kNames, m);
}

}  // namespace cumulo::render
