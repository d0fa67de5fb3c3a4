#include "engine/signals.h"

namespace napkin::engine {

int TestSignals::FindSlot(const std::string& slot) const {
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (slots[i] == slot) return static_cast<int>(i);
  return -1;
}

std::optional<double> TestSignals::PrefilteredCfc(Eigen::Index column) const {
  const auto index = static_cast<std::size_t>(column);
  return column >= 0 && index < prefiltered_cfc.size() ? prefiltered_cfc[index] : std::nullopt;
}

}  // namespace napkin::engine
