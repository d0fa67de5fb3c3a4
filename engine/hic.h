#pragma once
// HIC with its window, and HIC(d) (docs/algorithms.md "Injury criteria").
#include <Eigen/Core>
#include <atomic>
#include <limits>
#include <vector>

#include "engine/summary.h"

namespace napkin::engine {

// ---------------------------------------------------------------------------
// HIC
//
// Samples a_k (g) at t_k = t0 + k dt. With the cumulative trapezoid integral
//   V_0 = 0,  V_k = V_{k-1} + dt (a_{k-1} + a_k) / 2,
// a window i < j (ends on sample points) has duration d = (j - i) dt and
//   HIC(i, j) = d (I / d)^2.5,  I = V_j - V_i,
// and HIC = max over windows with d <= W (windows of exactly W included; W is
// taken as floor(W / dt) steps with a 1e-9 relative tolerance).
// Conventions:
//  * Windows with a non-positive integral (I <= 0) score nothing: the mean
//    is clamped at 0 (NHTSA integrates the resultant, which is >= 0; for
//    general signals a negative mean has no meaningful 2.5 power).
//  * Ties: the earliest t1, then the earliest t2, among the windows of the
//    largest value (values compared as computed doubles).
//  * No window with a positive integral (or fewer than 2 samples): value 0,
//    t1 = t2 = the first sample used.
//  * from_time_zero (NHTSA's program): integrate |a| and ignore samples
//    with t < 0 (t_k < -1e-9 dt).
// Throws InputError on a non-positive dt, a non-positive window or a
// non-finite sample (naming the sample and its time).

inline constexpr double kUnlimitedHicWindow = std::numeric_limits<double>::infinity();
inline constexpr double kHic15Window = 0.015;
inline constexpr double kHic36Window = 0.036;

struct HicOptions {
  double window_s = kUnlimitedHicWindow;  // largest t2 - t1; infinity = no limit
  bool from_time_zero = false;            // integrate |a|, ignore samples before t = 0
};

// Fast HIC: branch and bound over pairs of blocks of t1 and t2, with a
// segment tree of max V, min V and max per-step increment of V; returns
// exactly (value, t1, t2) of HicExhaustive.
HicWindow Hic(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
              const HicOptions& options = {});

// Hic for several window limits of one signal, in the order given: the
// integral and the search tree are built once, and each limit's search
// starts from the best window of the next shorter limit (a window of every
// longer limit), so the answers are Hic's, bit for bit.
// Throws Cancelled once `cancel` is set (engine/cancellation.h).
std::vector<HicWindow> HicForWindows(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                                     const std::vector<double>& windows_s, bool from_time_zero = false,
                                     const std::atomic<bool>* cancel = nullptr);

// HicForWindows with its integral and search tree in `work`'s memory, handed
// back when done (on a throw it is lost, and allocated again next time), so
// a loop over tests of one length maps no new pages (engine/pipeline.h Workspace).
struct HicWork {
  Eigen::VectorXd integral;          // the cumulative integral
  std::vector<double> max_integral;  // the segment tree
  std::vector<double> min_integral;
  std::vector<double> max_step;
};
std::vector<HicWindow> HicForWindows(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                                     const std::vector<double>& windows_s, bool from_time_zero,
                                     const std::atomic<bool>* cancel, HicWork& work);

// The reference: every window, O(n * W / dt).
HicWindow HicExhaustive(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                        const HicOptions& options = {});

// ---------------------------------------------------------------------------
// HIC(d), the free-motion headform's HIC of FMVSS No. 201 (49 CFR 571.201,
// S6.3: the upper interior impact requirement): HIC(d) = 0.75446 HIC36 +
// 166.4, a linear map of the HIC with windows up to 36 ms that makes the
// headform's number comparable to a whole dummy's (docs/algorithms.md
// "Injury criteria"). A NaN HIC36 gives a NaN HIC(d).
inline constexpr double kHicDSlope = 0.75446;
inline constexpr double kHicDOffset = 166.4;
inline double HicD(double hic36) { return kHicDSlope * hic36 + kHicDOffset; }

}  // namespace napkin::engine
