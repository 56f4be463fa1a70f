#pragma once
// Budget modes: the frame rate a run targets. The renderer reads the mode to choose pass variants and
// resolutions (DESIGN.md "Budget modes": e.g. the cloud march as one full-resolution pass at 30 Hz, or
// split at 200 m into a half-resolution near pass and a full-resolution far pass at 40/60 Hz, 2023 talk).
#include <cstdint>
#include <string>

namespace cumulo::render {

enum class BudgetMode : uint8_t { Hz30 = 30, Hz40 = 40, Hz60 = 60 };

inline int budget_hz(BudgetMode m) { return static_cast<int>(m); }
inline double budget_frame_seconds(BudgetMode m) { return 1.0 / budget_hz(m); }
inline double budget_frame_ms(BudgetMode m) { return 1000.0 / budget_hz(m); }

// "30", "40" or "60" (also "30hz"); throws cumulo::Error naming the accepted values otherwise.
BudgetMode parse_budget_mode(const std::string& text);
const char* budget_mode_name(BudgetMode m);  // "30 Hz"

}  // namespace cumulo::render
