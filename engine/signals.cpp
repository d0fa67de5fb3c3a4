#include "engine/signals.h"

namespace napkin::engine {

int TestSignals::FindSlot(const std::string& slot) const {
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (slots[i] == slot) return static_cast<int>(i);
  return -1;
}

}  // namespace napkin::engine
