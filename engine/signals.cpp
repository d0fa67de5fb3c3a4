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

std::optional<std::int64_t> TestSignals::FileRowOf(Eigen::Index k) const {
  if (k < 0 || static_cast<std::size_t>(samples.rows()) != file_rows.size() || k >= samples.rows())
    return std::nullopt;
  return file_rows[static_cast<std::size_t>(k)];
}

}  // namespace napkin::engine
