#include "records/test_record.h"

#include <optional>

#include "common/error.h"

namespace napkin::records {

std::vector<std::string> SlotUnits(const engine::ArrayGeometry& array,
                                   const std::vector<std::string>& slots) {
  std::vector<std::string> units;
  units.reserve(slots.size());
  for (const std::string& slot : slots) {
    const std::optional<std::size_t> sensor = array.FindSlot(slot);
    if (!sensor) throw InputError("channel '" + slot + "' is not a slot of array '" + array.name + "'.");
    units.push_back(array.sensors[*sensor].unit);
  }
  return units;
}

}  // namespace napkin::records
