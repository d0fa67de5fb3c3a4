#pragma once
// The `seed` solver: LC_COMP of report Appendix B, reproduced step by step
// for legacy comparison (REAL*4 arithmetic, coplanar estimate eq. 2.1-11/A-1,
// Appendix A compensation with the errata for c2 and c7, forward-Euler body
// angular velocity, direction-cosine update T <- T + T Omega dt with
// sub-steps |omega| dt <= 1 mrad, CG centripetal correction eq. A-12,
// trapezoidal velocity). Its purpose is to reproduce legacy results, not
// accuracy. Only for 3-2-2-2 arrays (the nine slots of kNapSlots).
#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"

namespace napkin::engine {

// Throws InvalidArrayError when `array` is not a 3-2-2-2 array with the
// Table 2-1 sense axes.
Kinematics SolveSeed(const ArrayGeometry& array, const TestSignals& signals, const InitialState& initial);

}  // namespace napkin::engine
