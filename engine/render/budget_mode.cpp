#include "engine/render/budget_mode.h"

#include <algorithm>
#include <cctype>

#include "engine/core/error.h"

namespace cumulo::render {

BudgetMode parse_budget_mode(const std::string& text) {
  std::string t;
  for (char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t.size() > 2 && t.substr(t.size() - 2) == "hz") t.resize(t.size() - 2);
  if (t == "30") return BudgetMode::Hz30;
  if (t == "40") return BudgetMode::Hz40;
  if (t == "60") return BudgetMode::Hz60;
  fail("budget mode \"%s\": expected 30, 40 or 60", text.c_str());
}

const char* budget_mode_name(BudgetMode m) {
  switch (m) {
    case BudgetMode::Hz30: return "30 Hz";
    case BudgetMode::Hz40: return "40 Hz";
    case BudgetMode::Hz60: return "60 Hz";
  }
  return "?";
}

}  // namespace cumulo::render
