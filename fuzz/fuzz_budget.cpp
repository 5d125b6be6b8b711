// Fuzz target: the budgets. The power budget (GLBUDGET_POWER, `glbudget run --power`): "40%",
// "35W", "off"; and the error budget (GLBUDGET_ERROR, `glbudget run --error`): "0.02". Input:
// the value, given to both. A budget that parses must be usable: a share in [0, 1] or watts
// >= 0; an error in [0, 1].
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "glbudget/model/selection.hpp"

namespace model = glbudget::model;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (const std::optional<double> error = model::parse_error_budget(text); error && !(*error >= 0.0 && *error <= 1.0))
    std::abort();
  const std::optional<model::Budget> budget = model::parse_budget(text);
  if (!budget) return 0;
  switch (budget->kind) {
    case model::Budget::Kind::Off:
      break;
    case model::Budget::Kind::ShareOfRange:
      if (!(budget->value >= 0.0 && budget->value <= 1.0)) std::abort();
      break;
    case model::Budget::Kind::Watts:
      if (!(std::isfinite(budget->value) && budget->value >= 0.0)) std::abort();
      break;
  }
  const double predicted[] = {10.0, 20.0, 30.0};
  const double error[] = {0.0, 0.1, 0.2};
  const model::Selection chosen = model::select_configuration(predicted, error, *budget);
  if (chosen.index >= 3) std::abort();
  return 0;
}
