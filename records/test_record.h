#pragma once
// The pieces of a test's catalogue record that come from its array.
#include <string>
#include <vector>

#include "engine/array_geometry.h"

namespace napkin::records {

// The unit `array` gives each of `slots` (the raw channels' units, in slot
// order). Throws InputError naming the first slot that is not a slot of
// the array.
std::vector<std::string> SlotUnits(const engine::ArrayGeometry& array, const std::vector<std::string>& slots);

}  // namespace napkin::records
