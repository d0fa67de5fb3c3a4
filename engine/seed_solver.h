#pragma once
// The `seed` solver: LC_COMP of report Appendix B, reproduced step by step
// for legacy comparison (REAL*4 arithmetic, coplanar estimate eq. 2.1-11/A-1,
// Appendix A compensation with the errata for c2 and c7, forward-Euler body
// angular velocity, direction-cosine update T <- T + T Omega dt with
// sub-steps |omega| dt <= 1 mrad, CG centripetal correction eq. A-12,
// trapezoidal velocity). Its purpose is to reproduce legacy results, not
// accuracy. Only for 3-2-2-2 arrays (the nine slots of kNapSlots).
#include <Eigen/Core>
#include <atomic>

#include "engine/array_geometry.h"
#include "engine/kinematics.h"
#include "engine/signals.h"

namespace napkin::engine {

// Throws InvalidArrayError when `array` is not a 3-2-2-2 array with the
// Table 2-1 sense axes, InputError when the signals lack one of the nine
// slots or hold a non-finite sample. Sensors other than the nine NAP slots
// (e.g. angular-rate sensors) are ignored: LC_COMP has no use for them.
// Throws Cancelled once `cancel` is set (read every kCancellationStride
// samples; engine/cancellation.h).
Kinematics SolveSeed(const ArrayGeometry& array, const TestSignals& signals, const InitialState& initial,
                     const std::atomic<bool>* cancel = nullptr);

namespace seed_detail {

// The listing's geometry block (inches, REAL*4), derived from the array:
// rx, ry, rz are the arm lengths to xarm_z, yarm_z, zarm_x; d0x..d3y are the
// offsets of each accelerometer from its ideal coplanar location (Appendix
// A's delta_ijk, index k = 1, 2, 3 -> x, y, z).
struct SeedGeometry {
  float rx = 0, ry = 0, rz = 0;
  Eigen::Vector3f d0x, d0y, d0z;  // cg_x, cg_y, cg_z
  Eigen::Vector3f d1y, d1z;       // xarm_y, xarm_z relative to (rx, 0, 0)
  Eigen::Vector3f d2x, d2z;       // yarm_x, yarm_z relative to (0, ry, 0)
  Eigen::Vector3f d3x, d3y;       // zarm_x, zarm_y relative to (0, 0, rz)
};

// Throws InvalidArrayError as SolveSeed does.
SeedGeometry SeedGeometryOf(const ArrayGeometry& array);

using SeriesF3 = Eigen::Matrix<float, Eigen::Dynamic, 3>;
// The per-sample outputs of LC_COMP in the listing's own units and types
// (g, rad/s, rad/s^2, in/s, deg; REAL*4 except T), row k = listing sample
// i = k + 1, for step-by-step comparison with the reference program.
struct ListingTrace {
  Eigen::VectorXf time;                                 // time = i*del (REAL*4)
  SeriesF3 facc_g;                                      // faccx, faccy, faccz
  SeriesF3 bomeg;                                       // bomegxx, bomegyy, bomegzz
  SeriesF3 bomegd;                                      // compensated bomegdx, bomegdy, bomegdz
  SeriesF3 bacc_cg_g;                                   // bacc(1..3) after the CG correction
  SeriesF3 fomegd;                                      // fomegdx, fomegdy, fomegdz
  SeriesF3 fomeg;                                       // fomegx, fomegy, fomegz
  SeriesF3 fvel_inps;                                   // fvelx, fvely, fvelz
  SeriesF3 alpha_beta_gamma_deg;                        // the listing's +-90 deg extraction, as `notrunc`
  SeriesF3 ang_deg;                                     // ang1, ang2, ang3
  Eigen::Matrix<double, Eigen::Dynamic, 9> t_rowmajor;  // T11 T12 ... T33 (DOUBLE)
};

// Runs the listing on the nine NAP channels of `signals`.
ListingTrace RunListing(const ArrayGeometry& array, const TestSignals& signals, const InitialState& initial,
                        const std::atomic<bool>* cancel = nullptr);

}  // namespace seed_detail
}  // namespace napkin::engine
