#pragma once
// Head injury criteria (docs/algorithms.md "Injury criteria"): a3ms and BrIC
// here, HIC (engine/hic.h) and DAMAGE (engine/damage.h), and FillCriteria, which
// computes every criterion of a result.
#include <Eigen/Core>
#include <atomic>
#include <limits>
#include <vector>

#include "engine/damage.h"
#include "engine/hic.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "engine/summary.h"

namespace napkin::engine {

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
// Fills hic15, hic36, hic (resultant of acc_fixed in g, config.hic), hic_d, a3ms_g (config.a3ms),
// bric (omega_body, config.bric), damage (alpha_body), every criterion a
// summary-field row computes (SummaryField::compute, e.g. UBrIC) and the
// injury risks (engine/injury_risk.h) of `summary`. The
// time base must be uniform (dt: kinematics.dt_s, else from the first and
// last samples; windows are found on sample indices, so a record starting
// far from t = 0 gets the windows of one starting at 0); throws
// InputError when there are fewer than 2 samples, Cancelled once `cancel`
// is set (engine/cancellation.h).
// `work` (null: memory of its own) keeps what the criteria compute along the
// way for the next test, so a loop over tests of one length maps no new
// pages (engine/pipeline.h Workspace).
struct CriteriaWork {
  Eigen::VectorXd resultant_g;      // |acc| in g (HIC, a3ms)
  HicWork hic;                      // HIC's integral and search tree
  std::vector<double> a3ms_values;  // a3ms's partial sort
  Series3 damage_displacement;      // DAMAGE's model response
};
void FillCriteria(const Kinematics& kinematics, const ProcessingConfig& config, TestSummary& summary,
                  const std::atomic<bool>* cancel = nullptr, CriteriaWork* work = nullptr);

}  // namespace napkin::engine
