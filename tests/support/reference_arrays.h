#pragma once
// The report's array geometries as test data (positions in inches, Table 2-1
// sense axes), independent of the JSON presets in config/arrays/ so tests can
// check the presets against them.
#include "engine/array_geometry.h"

namespace napkin::test_support {

// Table 4-1, idealized coplanar 3-2-2-2 (arms 2.2, 1.9, 3.2 in).
engine::ArrayGeometry Ideal3222();
// Table 4-2, general non-coplanar geometry (LC_COMP's commented-out block).
engine::ArrayGeometry VolpeTable42();
// Appendix A, "Position of accelerometers in Denton 3-2-2-2".
engine::ArrayGeometry Denton3222();
// Three accelerometers at the CG plus three angular-rate sensors.
engine::ArrayGeometry SixAOmegaCg();
// Three accelerometers at the CG along x, y, z: acceleration only (3a-cg).
engine::ArrayGeometry ThreeACg();
// Denton NAP plus three angular-rate sensors (12 channels).
engine::ArrayGeometry NapArs12();
// Array "test" of two sensors without positions, for conditioning tests: a
// linear accelerometer in slot cg_x and an angular-rate sensor (rad/s) in ars_x.
engine::ArrayGeometry OneLinearOneRate();

}  // namespace napkin::test_support
