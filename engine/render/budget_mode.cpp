#include "engine/render/budget_mode.h"

#include <algorithm>
#include <cctype>

#include "engine/core/error.h"
#include "engine/core/message.h"

namespace cumulo::render {

BudgetMode parse_budget_mode(const std::string& text) {
  std::string t;
  for (char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t.size() > 2 && t.substr(t.size() - 2) == "hz") t.resize(t.size() - 2);
  if (const std::optional<BudgetMode> m = parse_name(kBudgetModeFlagNames, t)) return *m;
  fail("budget mode %s: expected %s", quote(text).c_str(), names_list(kBudgetModeFlagNames).c_str());
}

}  // namespace cumulo::render
