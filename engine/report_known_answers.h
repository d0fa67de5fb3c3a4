#pragma once
// The report's known answers, in one place for the tests and `napkin demo`
// ("computed vs known"). Pure data: no I/O, no code.
//
// "Report" is the 1995 report (shared/seed/000_4a0f813f9bdc0a55.txt, an OCR
// with errors); where it states a value only roughly, the value here is the
// one docs/algorithms.md "Known answers" derives from the report's scenario
// definition, and the comment says so. Tolerances stay with each check: they
// depend on what is compared (truth, exact solver, text output), not on the
// answer.
#include <numbers>

#include "engine/units.h"

namespace napkin::engine::report {

// ---------------------------------------------------------------------------
// Report section 4.5 (`synth --scenario seed-fixed-axis`): rotation about an
// axis parallel to fixed Y, 10 in from the CG; omega_Y(t) = 25 (1 - cos(2 pi
// t / 60 ms)) rad/s for 0 <= t <= 60 ms, then 0 (section 4.5.2); head
// initially rotated 0.5 rad about body x, y, z (section 4.5.1); 100 ms at
// 10 kHz.

// Total rotation about fixed Y: the integral of omega_Y, 25 rad/s * 60 ms.
// Section 4.5.2: "the resulting angular displacement about the fixed lateral
// axis is 85.94 degrees" (also 4.5.4).
inline constexpr double kTotalRotationRad = 1.5;
// 1.5 rad in degrees to four decimals (docs/algorithms.md table: 85.9437 deg;
// exactly 85.943669...).
inline constexpr double kTotalRotationDeg = 85.9437;

// Peak fixed omega_Y, twice the 25 rad/s amplitude. Section 4.5.2: "a peak
// angular velocity of 50 rad/sec".
inline constexpr double kPeakOmegaFixedYRadps = 50.0;
// Fixed omega_X and omega_Z: zero, the motion is solely about fixed Y.
// Section 4.5.4 (Figure 4-19: "reduced to zero in the fixed coordinate
// system"); docs/algorithms.md table "fixed omega_X, omega_Z: 0, 0".
inline constexpr double kOmegaFixedXZRadps = 0.0;

// Peak angular acceleration, 25 * 2 pi / 0.06 = 2617.99 rad/s^2. Section
// 4.5.2 says "approximately 2500 rad/sec^2"; docs/algorithms.md table: 2618.
inline constexpr double kPeakAlphaRadps2 = 2618.0;
// The same peak to two decimals (2617.9939 rounded), for checks of the truth.
inline constexpr double kPeakAlphaRadps2TwoDecimals = 2617.99;

// Peak resultant CG acceleration, 10 in * sqrt(omega_dot^2 + omega^4) at its
// peak, in g. docs/algorithms.md table (the report plots it, Figure 4-13;
// computed: 70.4093).
inline constexpr double kPeakAccG = 70.41;

// HIC, unlimited window. Section 4.5.2: "a HIC value of 1583 with (t2 - t1)
// = 54.3 - 5.73 = 48.54 msec"; docs/algorithms.md table: 1583.26, t1 = 5.7 ms,
// t2 = 54.3 ms (+-0.1 ms by sampling rate; computed at 10 kHz: 1583.2623).
inline constexpr double kHic = 1583.26;
inline constexpr double kHicT1S = 0.0057;
inline constexpr double kHicT2S = 0.0543;

// HIC36 (window <= 36 ms). docs/algorithms.md table (not in the report):
// 1348.70 over 12.0 ... 48.0 ms (computed: 1348.698).
inline constexpr double kHic36 = 1348.70;
inline constexpr double kHic36T1S = 0.0120;
inline constexpr double kHic36T2S = 0.0480;

// HIC15 (window <= 15 ms). docs/algorithms.md table (not in the report): 573.10,
// two equal maxima mirrored about t = 30 ms, either window (computed:
// 573.0994).
inline constexpr double kHic15 = 573.10;

// Section 4.5.5, Table 4-2 data transformed as ideal (Table 4-1) geometry,
// without compensation: fixed omega_X and omega_Z peak "about -2.5 rad/sec,
// or about 5 percent of the correct maximum angular velocity of 50 rad/sec".
inline constexpr double kUncompensatedCrossAxisFraction = 0.05;

// ---------------------------------------------------------------------------
// Report section 4.4 (`synth --scenario seed-sequential`): 90 deg about body
// x (0-40 ms), rest, 90 deg about body y (50-90 ms), rest, 90 deg about body z
// (100-140 ms). The final orientation is Rx(90 deg) Ry(90 deg) Rz(90 deg),
// "equivalent to sequential rotations of 90 degrees about the fixed X axis,
// followed by rotations about fixed Z and X axes" (section 4.4).
inline constexpr double kSequentialTurnRad = std::numbers::pi / 2;

// ---------------------------------------------------------------------------
// An independent HIC answer (docs/algorithms.md "Known answers", not from the
// report): a(t) = sin(20 pi t) g, t = 0 ... 0.05 s at 10 kHz, HIC over a
// window <= 30 ms is 0.02048 at [0.0100, 0.0400] s (the window centred on
// the peak; computed: 0.020480).
inline constexpr double kHalfSineHicWindowS = 0.030;
inline constexpr double kHalfSineHic = 0.02048;
inline constexpr double kHalfSineHicT1S = 0.0100;
inline constexpr double kHalfSineHicT2S = 0.0400;

}  // namespace napkin::engine::report
