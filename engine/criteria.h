#pragma once
// Head injury criteria (docs/algorithms.md "Injury criteria"): HIC (with its
// window), a3ms, BrIC and DAMAGE.
#include <Eigen/Core>
#include <atomic>
#include <limits>
#include <vector>

#include "engine/kinematics.h"
#include "engine/processing.h"
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

// ---------------------------------------------------------------------------
// a3ms: the highest level exceeded for a cumulative (not necessarily
// continuous) 3 ms. Each sample stands for dt of time, so with
// N = ceil(duration / dt) (1e-9 relative tolerance) it is the largest L such
// that at least N samples are >= L, i.e. the N-th largest sample.
// Throws InputError when the record has fewer than N samples.
inline constexpr double kA3msDurationS = 0.003;
double A3ms(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s = kA3msDurationS);

// a3ms, continuous definition (processing config "a3ms": {"definition":
// "continuous"}): the highest level the signal stays at or above for an
// unbroken 3 ms, i.e. the largest minimum over N consecutive samples (N as
// above). Never above A3ms(); equal to it for a pulse with one peak. Throws
// InputError as A3ms() does.
double A3msContinuous(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s,
                      double duration_s = kA3msDurationS);

// ---------------------------------------------------------------------------
// BrIC (Takhounts et al. 2013) = sqrt(sum_i (max_t |omega_i| / omega_iC)^2),
// omega in body axes (rad/s). Throws InputError on non-positive critical values.
double Bric(const Eigen::Ref<const Series3>& omega_body_radps, const Eigen::Vector3d& critical_radps);

// ---------------------------------------------------------------------------
// DAMAGE (Gabler et al. 2019): the coupled mass-spring-damper
//   M d'' + C d' + K d = M alpha(t),   d(t0) = d'(t0) = 0,
// driven by the body angular acceleration (rad/s^2), with
//   M = m I, K = [[kxx+kxy+kxz, -kxy, -kxz], [-kxy, kxy+kyy+kyz, -kyz],
//                 [-kxz, -kyz, kxz+kyz+kzz]],  C = a1 K,
//   DAMAGE = beta * max_k ||d(t_k)||.
// Integrated exactly for alpha linear between samples (state-space
// discretisation by one matrix exponential of the system augmented with the
// input and its slope), so the only error is the linear interpolation of alpha.
struct DamageModel {
  double mass_kg = 1.0;        // m, each axis
  double kxx = 32142.0;        // N/m
  double kyy = 23493.0;        // N/m
  double kzz = 16935.0;        // N/m
  double kxy = 0.0;            // N/m
  double kyz = 0.0;            // N/m
  double kxz = 1636.3;         // N/m
  double a1_s = 5.9148e-3;     // stiffness-proportional damping, C = a1 K (s)
  double beta_per_m = 2.9903;  // DAMAGE = beta * max ||d||

  Eigen::Matrix3d Stiffness() const;
};

// Displacement d(t_k) (m) of the DAMAGE model at every sample. Throws
// Cancelled once `cancel` is set (engine/cancellation.h).
Series3 DamageDisplacement(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s,
                           const DamageModel& model = {}, const std::atomic<bool>* cancel = nullptr);
double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model = {},
              const std::atomic<bool>* cancel = nullptr);

// ---------------------------------------------------------------------------
// Fills hic15, hic36, hic (resultant of acc_fixed in g, config.hic), hic_d, a3ms_g (config.a3ms),
// bric (omega_body, config.bric), damage (alpha_body) and the injury risks
// (engine/injury_risk.h) of `summary`. The
// time base must be uniform (dt: kinematics.dt_s, else from the first and
// last samples; windows are found on sample indices, so a record starting
// far from t = 0 gets the windows of one starting at 0); throws
// InputError when there are fewer than 2 samples, Cancelled once `cancel`
// is set (engine/cancellation.h).
// `work` (null: memory of its own) keeps what the criteria compute along the
// way for the next test, so a loop over tests of one length maps no new
// pages (engine/pipeline.h Workspace).
struct CriteriaWork {
  Eigen::VectorXd resultant_g;           // |acc| in g (HIC, a3ms)
  Eigen::VectorXd hic_integral;          // HIC's cumulative integral
  std::vector<double> hic_max_integral;  // HIC's segment tree
  std::vector<double> hic_min_integral;
  std::vector<double> hic_max_step;
  std::vector<double> a3ms_values;  // a3ms's partial sort
  Series3 damage_displacement;      // DAMAGE's model response
};
void FillCriteria(const Kinematics& kinematics, const ProcessingConfig& config, TestSummary& summary,
                  const std::atomic<bool>* cancel = nullptr, CriteriaWork* work = nullptr);

}  // namespace napkin::engine
