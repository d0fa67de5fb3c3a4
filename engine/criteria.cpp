#include "engine/criteria.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "common/error.h"
#include "engine/units.h"

namespace napkin::engine {

namespace {

void CheckInterval(double dt_s, const char* what) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) {
    std::ostringstream message;
    message << what << ": the sampling interval " << dt_s << " s is not a finite positive number.";
    throw InputError(message.str());
  }
}

void CheckFiniteSamples(const Eigen::Ref<const Eigen::VectorXd>& values, double dt_s, double t0_s,
                        const char* what) {
  for (Eigen::Index k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      std::ostringstream message;
      message << what << ": sample " << k << " (t = " << t0_s + static_cast<double>(k) * dt_s
              << " s) is not finite.";
      throw InputError(message.str());
    }
  }
}

// ---------------------------------------------------------------------------
// HIC

// The samples HIC works on, with their cumulative trapezoid integral.
struct HicProblem {
  Eigen::Index first = 0;      // index (in the input) of the first sample used
  Eigen::Index count = 0;      // number of samples used
  Eigen::Index max_steps = 0;  // longest window, in sampling intervals
  Eigen::VectorXd integral;    // V_k, k = 0..count-1 (g s)
};

HicProblem PrepareHic(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                      const HicOptions& options) {
  CheckInterval(dt_s, "HIC");
  if (!std::isfinite(t0_s)) throw InputError("HIC: the time of the first sample is not finite.");
  if (std::isnan(options.window_s) || !(options.window_s > 0.0)) {
    std::ostringstream message;
    message << "HIC: the window " << options.window_s << " s is not positive.";
    throw InputError(message.str());
  }
  CheckFiniteSamples(acc_g, dt_s, t0_s, "HIC");
  HicProblem problem;
  const Eigen::Index n = acc_g.size();
  if (options.from_time_zero) {
    const double tolerance = 1e-9 * dt_s;
    while (problem.first < n && t0_s + static_cast<double>(problem.first) * dt_s < -tolerance)
      ++problem.first;
  }
  problem.count = n - problem.first;
  problem.integral.resize(problem.count);
  if (problem.count == 0) return problem;
  const auto value = [&](Eigen::Index k) {
    const double a = acc_g[problem.first + k];
    return options.from_time_zero ? std::abs(a) : a;
  };
  problem.integral[0] = 0.0;
  for (Eigen::Index k = 1; k < problem.count; ++k)
    problem.integral[k] = problem.integral[k - 1] + 0.5 * dt_s * (value(k - 1) + value(k));
  const Eigen::Index longest = problem.count - 1;
  if (std::isinf(options.window_s)) {
    problem.max_steps = longest;
  } else {
    // Windows of exactly W are included; W / dt is rarely an exact double.
    const double steps = std::floor(options.window_s / dt_s * (1.0 + 1e-9));
    problem.max_steps = steps >= static_cast<double>(longest) ? longest : static_cast<Eigen::Index>(steps);
  }
  return problem;
}

// HIC of window (i, j) with integral > 0. Both searches call exactly this,
// so equal windows give bit-equal values.
inline double HicValue(const double* integral, Eigen::Index i, Eigen::Index j, double dt_s) {
  const double area = integral[j] - integral[i];
  const double duration = static_cast<double>(j - i) * dt_s;
  const double mean = area / duration;
  return duration * std::pow(mean, 2.5);
}

// Best window so far with the tie rule: larger value, then earlier t1, then
// earlier t2.
struct HicBest {
  double value = 0.0;
  Eigen::Index i = -1;
  Eigen::Index j = -1;

  bool IsBeatenBy(double v, Eigen::Index vi, Eigen::Index vj) const {
    if (v != value) return v > value;
    if (i < 0) return false;  // no window yet: a zero value does not count
    return vi < i || (vi == i && vj < j);
  }
};

HicWindow MakeHicWindow(const HicProblem& problem, const HicBest& best, double dt_s, double t0_s) {
  const auto time_at = [&](Eigen::Index k) { return t0_s + static_cast<double>(problem.first + k) * dt_s; };
  HicWindow window;
  if (best.i < 0) {
    window.value = 0.0;
    window.t1_s = window.t2_s = time_at(0);
  } else {
    window.value = best.value;
    window.t1_s = time_at(best.i);
    window.t2_s = time_at(best.j);
  }
  return window;
}

// Segment tree over t2 indices: node h covers [lo, hi]; max_integral =
// max V, max_step = max (V_{k+1} - V_k) over the steps inside [lo, hi].
struct HicSegmentTree {
  Eigen::Index leaves = 0;
  std::vector<double> max_integral;
  std::vector<double> max_step;
};

HicSegmentTree BuildHicSegmentTree(const double* integral, Eigen::Index count) {
  const double minus_inf = -std::numeric_limits<double>::infinity();
  HicSegmentTree tree;
  const auto leaves = static_cast<Eigen::Index>(std::bit_ceil(static_cast<std::size_t>(count)));
  tree.leaves = leaves;
  tree.max_integral.assign(static_cast<std::size_t>(2 * leaves), minus_inf);
  tree.max_step.assign(static_cast<std::size_t>(2 * leaves), minus_inf);
  std::vector<double>& max_integral = tree.max_integral;
  std::vector<double>& max_step = tree.max_step;
  for (Eigen::Index k = 0; k < count; ++k) max_integral[static_cast<std::size_t>(leaves + k)] = integral[k];
  for (Eigen::Index width = 2, first_node = leaves / 2; first_node >= 1; width *= 2, first_node /= 2) {
    for (Eigen::Index h = first_node; h < 2 * first_node; ++h) {
      const auto left = static_cast<std::size_t>(2 * h), right = left + 1;
      const Eigen::Index boundary =
          (h - first_node) * width + width / 2 - 1;  // step boundary -> boundary + 1
      const double boundary_step =
          boundary + 1 < count ? integral[boundary + 1] - integral[boundary] : minus_inf;
      max_integral[static_cast<std::size_t>(h)] = std::max(max_integral[left], max_integral[right]);
      max_step[static_cast<std::size_t>(h)] = std::max({max_step[left], max_step[right], boundary_step});
    }
  }
  return tree;
}

// Largest |V_{k+1} - V_k|: the scale of the rounding slack on integrals.
double MaxAbsStep(const double* integral, Eigen::Index count) {
  double max_abs_step = 0.0;
  for (Eigen::Index k = 0; k + 1 < count; ++k)
    max_abs_step = std::max(max_abs_step, std::abs(integral[k + 1] - integral[k]));
  return max_abs_step;
}

// (d dt)^0.6 for every window length d = 0 .. max_steps.
std::vector<double> DurationPowers(Eigen::Index max_steps, double dt_s) {
  std::vector<double> duration_pow(static_cast<std::size_t>(max_steps + 1));
  for (Eigen::Index d = 0; d <= max_steps; ++d)
    duration_pow[static_cast<std::size_t>(d)] = std::pow(static_cast<double>(d) * dt_s, 0.6);
  return duration_pow;
}

// The largest step of V in [i, i + block) for every i, from running maxima
// over blocks of `block` steps (van Herk / Gil-Werman): the larger of
// suffix[i] and prefix[i + block - 1].
struct StepBlockMaxima {
  std::vector<double> prefix;
  std::vector<double> suffix;
};

StepBlockMaxima BlockStepMaxima(const double* integral, Eigen::Index step_count, Eigen::Index block) {
  StepBlockMaxima maxima;
  maxima.prefix.resize(static_cast<std::size_t>(step_count));
  maxima.suffix.resize(static_cast<std::size_t>(step_count));
  for (Eigen::Index k = 0; k < step_count; ++k) {
    const double step = integral[k + 1] - integral[k];
    const auto uk = static_cast<std::size_t>(k);
    maxima.prefix[uk] = (k % block == 0) ? step : std::max(maxima.prefix[uk - 1], step);
  }
  for (Eigen::Index k = step_count - 1; k >= 0; --k) {
    const double step = integral[k + 1] - integral[k];
    const auto uk = static_cast<std::size_t>(k);
    maxima.suffix[uk] =
        (k == step_count - 1 || (k + 1) % block == 0) ? step : std::max(maxima.suffix[uk + 1], step);
  }
  return maxima;
}

}  // namespace

HicWindow HicExhaustive(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                        const HicOptions& options) {
  const HicProblem problem = PrepareHic(acc_g, dt_s, t0_s, options);
  const double* integral = problem.integral.data();
  HicBest best;
  for (Eigen::Index i = 0; i + 1 < problem.count; ++i) {
    const Eigen::Index last = std::min(problem.count - 1, i + problem.max_steps);
    for (Eigen::Index j = i + 1; j <= last; ++j) {
      if (!(integral[j] - integral[i] > 0.0)) continue;
      const double value = HicValue(integral, i, j, dt_s);
      if (best.IsBeatenBy(value, i, j)) best = {value, i, j};
    }
  }
  return MakeHicWindow(problem, best, dt_s, t0_s);
}

// Branch and bound. For a fixed t1 (index i) and a block of t2 indices
// [lo, hi] (s = j - lo steps into the block, d0 = lo - i), two upper bounds
// of the integral I(j) = V_j - V_i hold for every j in the block:
//   (A) I(j) <= I(lo) + s * max_step,  max_step = max over the block's steps
//       of V_{k+1} - V_k;  the bound g(s) = (I(lo) + s max_step)^2.5 /
//       (d0 + s)^1.5 has d/ds log g = 2.5 m / (I + s m) - 1.5 / (d0 + s),
//       whose sign changes at most once, from - to +, so g is largest at
//       s = 0 or s = hi - lo: testing both ends bounds the whole block;
//   (B) I(j) <= max V over the block - V_i, with the shortest duration d0.
// HIC > best  <=>  I > best^0.4 (d dt)^0.6, so both tests are products with
// a precomputed table of (d dt)^0.6. Bounds carry a 1e-9 relative margin and
// an absolute rounding slack on the integral, so no window that could beat
// (or tie) the best is ever pruned. Windows are visited in the exhaustive
// order (t1, then t2, ascending) and compared with the same tie rule, so the
// result is the exhaustive one, bit for bit.
HicWindow Hic(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
              const HicOptions& options) {
  const HicProblem problem = PrepareHic(acc_g, dt_s, t0_s, options);
  const Eigen::Index count = problem.count;
  HicBest best;
  if (count < 2) return MakeHicWindow(problem, best, dt_s, t0_s);
  const double* integral = problem.integral.data();

  const HicSegmentTree tree = BuildHicSegmentTree(integral, count);
  const double max_abs_step = MaxAbsStep(integral, count);
  const std::vector<double> duration_pow = DurationPowers(problem.max_steps, dt_s);

  constexpr double kRelativeMargin = 1.0 - 1e-9;
  constexpr double kRoundingSlack = 8.0 * std::numeric_limits<double>::epsilon();
  double threshold_scale = 0.0;  // best^0.4 * margin
  const auto update_threshold = [&]() { threshold_scale = std::pow(best.value, 0.4) * kRelativeMargin; };

  // Bounded windows: a t1 whose whole window range cannot beat the best is
  // skipped in O(1): I(j) <= (j - i) max_step and (s A)^2.5 / (s dt)^1.5
  // grows with s.
  const bool bounded = problem.max_steps < count - 1;
  const StepBlockMaxima block_max =
      bounded ? BlockStepMaxima(integral, count - 1, problem.max_steps) : StepBlockMaxima{};

  struct NodeRange {
    Eigen::Index node, lo, hi;
  };
  std::array<NodeRange, 2 * 64 + 2> stack{};

  for (Eigen::Index i = 0; i + 1 < count; ++i) {
    const Eigen::Index j_first = i + 1;
    const Eigen::Index j_last = std::min(count - 1, i + problem.max_steps);
    const double integral_i = integral[i];
    if (bounded) {
      const Eigen::Index span = j_last - i;
      const double largest_step = std::max(block_max.suffix[static_cast<std::size_t>(i)],
                                           block_max.prefix[static_cast<std::size_t>(j_last - 1)]);
      const double bound = static_cast<double>(span) * largest_step +
                           kRoundingSlack * static_cast<double>(span) * max_abs_step;
      if (!(bound > threshold_scale * duration_pow[static_cast<std::size_t>(span)])) continue;
    }
    std::size_t top = 0;
    stack[top++] = {1, 0, tree.leaves - 1};
    while (top > 0) {
      const NodeRange range = stack[--top];
      if (range.hi < j_first || range.lo > j_last) continue;
      const auto h = static_cast<std::size_t>(range.node);
      if (range.lo >= j_first && range.hi <= j_last) {
        const Eigen::Index d0 = range.lo - i;
        const double threshold_d0 = threshold_scale * duration_pow[static_cast<std::size_t>(d0)];
        if (range.lo == range.hi) {
          const double area = integral[range.lo] - integral_i;
          if (area > 0.0 && area > threshold_d0) {
            const double value = HicValue(integral, i, range.lo, dt_s);
            if (best.IsBeatenBy(value, i, range.lo)) {
              best = {value, i, range.lo};
              update_threshold();
            }
          }
          continue;
        }
        // (B) the largest integral anywhere in the block, shortest duration.
        if (!(tree.max_integral[h] - integral_i > threshold_d0)) continue;
        // (A) linear growth from the block start, tested at both ends.
        const Eigen::Index span = range.hi - range.lo;
        const double area_lo = integral[range.lo] - integral_i;
        const double slack = kRoundingSlack * (std::abs(area_lo) + static_cast<double>(span) * max_abs_step);
        const double bound_lo = area_lo + slack;
        const double bound_hi = area_lo + static_cast<double>(span) * tree.max_step[h] + slack;
        if (!(bound_lo > threshold_d0 ||
              bound_hi > threshold_scale * duration_pow[static_cast<std::size_t>(d0 + span)]))
          continue;
      }
      // Descend: push the right child first so t2 is visited in ascending order.
      const Eigen::Index mid = range.lo + (range.hi - range.lo) / 2;
      stack[top++] = {2 * range.node + 1, mid + 1, range.hi};
      stack[top++] = {2 * range.node, range.lo, mid};
    }
  }
  return MakeHicWindow(problem, best, dt_s, t0_s);
}

// ---------------------------------------------------------------------------

namespace {

// The number of samples that stand for `duration_s` (each stands for dt),
// after the checks both a3ms definitions share.
Eigen::Index A3msSamples(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  CheckInterval(dt_s, "a3ms");
  if (!(std::isfinite(duration_s) && duration_s > 0.0)) {
    std::ostringstream message;
    message << "a3ms: the duration " << duration_s << " s is not positive.";
    throw InputError(message.str());
  }
  CheckFiniteSamples(acc_g, dt_s, 0.0, "a3ms");
  const double needed = std::ceil(duration_s / dt_s * (1.0 - 1e-9));
  if (needed > static_cast<double>(acc_g.size())) {
    std::ostringstream message;
    message << "a3ms: the record (" << acc_g.size() << " samples at " << dt_s << " s) is shorter than "
            << duration_s << " s.";
    throw InputError(message.str());
  }
  return static_cast<Eigen::Index>(needed);
}

}  // namespace

double A3msContinuous(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  const Eigen::Index window = A3msSamples(acc_g, dt_s, duration_s);
  // Sliding-window minimum (a deque of indices of increasing values), O(n).
  std::vector<Eigen::Index> candidates(static_cast<std::size_t>(acc_g.size()));
  std::size_t head = 0, tail = 0;  // candidates[head, tail)
  double best = -std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k < acc_g.size(); ++k) {
    while (tail > head && acc_g[candidates[tail - 1]] >= acc_g[k]) --tail;
    candidates[tail++] = k;
    if (candidates[head] <= k - window) ++head;
    if (k + 1 >= window) best = std::max(best, acc_g[candidates[head]]);
  }
  return best;
}

double A3ms(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double duration_s) {
  const auto rank =
      static_cast<std::ptrdiff_t>(A3msSamples(acc_g, dt_s, duration_s)) - 1;  // 0-based, descending
  std::vector<double> values(acc_g.data(), acc_g.data() + acc_g.size());
  std::nth_element(values.begin(), values.begin() + rank, values.end(), std::greater<>());
  return values[static_cast<std::size_t>(rank)];
}

double Bric(const Eigen::Ref<const Series3>& omega_body_radps, const Eigen::Vector3d& critical_radps) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!(std::isfinite(critical_radps[axis]) && critical_radps[axis] > 0.0)) {
      std::ostringstream message;
      message << "BrIC: the critical angular velocity about axis "
              << "xyz"[axis] << " (" << critical_radps[axis] << " rad/s) is not positive.";
      throw InputError(message.str());
    }
  }
  if (omega_body_radps.rows() == 0) return 0.0;
  if (!omega_body_radps.allFinite()) throw InputError("BrIC: the angular velocity has a non-finite sample.");
  const Eigen::Vector3d peak = omega_body_radps.cwiseAbs().colwise().maxCoeff().transpose();
  return peak.cwiseQuotient(critical_radps).norm();
}

Eigen::Matrix3d DamageModel::Stiffness() const {
  Eigen::Matrix3d k;
  k << kxx + kxy + kxz, -kxy, -kxz,  //
      -kxy, kxy + kyy + kyz, -kyz,   //
      -kxz, -kyz, kxz + kyz + kzz;
  return k;
}

Series3 DamageDisplacement(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s,
                           const DamageModel& model) {
  CheckInterval(dt_s, "DAMAGE");
  if (!alpha_body_radps2.allFinite())
    throw InputError("DAMAGE: the angular acceleration has a non-finite sample.");
  if (!(std::isfinite(model.mass_kg) && model.mass_kg > 0.0))
    throw InputError("DAMAGE: the mass is not positive.");
  const Eigen::Index n = alpha_body_radps2.rows();
  Series3 displacement = Series3::Zero(n, 3);
  if (n < 2) return displacement;

  // x = [d; d'],  x' = A x + B alpha,  A = [[0, I], [-K/m, -C/m]],  B = [0; I].
  const Eigen::Matrix3d stiffness_per_mass = model.Stiffness() / model.mass_kg;
  Eigen::Matrix<double, 6, 6> system = Eigen::Matrix<double, 6, 6>::Zero();
  system.topRightCorner<3, 3>().setIdentity();
  system.bottomLeftCorner<3, 3>() = -stiffness_per_mass;
  system.bottomRightCorner<3, 3>() = -model.a1_s * stiffness_per_mass;
  // With alpha(t_k + s dt) = alpha_k + s (alpha_{k+1} - alpha_k), the
  // augmented state z = [x; alpha; delta_alpha] obeys dz/ds = Z z with
  // Z = [[A dt, B dt, 0], [0, 0, I], [0, 0, 0]]; exp(Z) = [[Phi, G0, G1], ...].
  Eigen::Matrix<double, 12, 12> augmented = Eigen::Matrix<double, 12, 12>::Zero();
  augmented.topLeftCorner<6, 6>() = system * dt_s;
  augmented.block<3, 3>(3, 6) = Eigen::Matrix3d::Identity() * dt_s;
  augmented.block<3, 3>(6, 9).setIdentity();
  const Eigen::Matrix<double, 12, 12> transition = augmented.exp();
  const Eigen::Matrix<double, 6, 6> phi = transition.topLeftCorner<6, 6>();
  const Eigen::Matrix<double, 6, 3> gamma_value = transition.block<6, 3>(0, 6);
  const Eigen::Matrix<double, 6, 3> gamma_slope = transition.block<6, 3>(0, 9);

  Eigen::Matrix<double, 6, 1> state = Eigen::Matrix<double, 6, 1>::Zero();
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    const Eigen::Vector3d alpha_k = alpha_body_radps2.row(k).transpose();
    const Eigen::Vector3d alpha_next = alpha_body_radps2.row(k + 1).transpose();
    state = phi * state + gamma_value * alpha_k + gamma_slope * (alpha_next - alpha_k);
    displacement.row(k + 1) = state.head<3>().transpose();
  }
  return displacement;
}

double Damage(const Eigen::Ref<const Series3>& alpha_body_radps2, double dt_s, const DamageModel& model) {
  const Series3 displacement = DamageDisplacement(alpha_body_radps2, dt_s, model);
  if (displacement.rows() == 0) return 0.0;
  return model.beta_per_m * displacement.rowwise().norm().maxCoeff();
}

// ---------------------------------------------------------------------------

void FillCriteria(const Kinematics& kinematics, const ProcessingConfig& config, TestSummary& summary) {
  const Eigen::Index n = kinematics.size();
  if (n < 2) throw InputError("injury criteria need at least 2 samples of kinematics.");
  // Windows are found on sample indices and their length is steps x dt, so
  // dt must not come from differences of absolute times: a record starting
  // at t0 ~ 2e5 s would lose digits (and a 15 ms window a step).
  const double t0 = kinematics.time_s[0];
  const double dt =
      kinematics.dt_s > 0.0 ? kinematics.dt_s : (kinematics.time_s[n - 1] - t0) / static_cast<double>(n - 1);
  CheckInterval(dt, "injury criteria");
  // An acceleration-only array's CG acceleration is known in body axes only
  // (docs/algorithms.md "Acceleration-only arrays"): its resultant is the same.
  const bool rotation = HasRotation(kinematics);
  const Eigen::VectorXd acc_g =
      rotation ? Eigen::VectorXd(kinematics.acc_fixed.rowwise().norm() / kStandardGravity)
               : Eigen::VectorXd(kinematics.acc_body.rowwise().norm() / kStandardGravity);

  HicOptions options;
  options.from_time_zero = config.hic.from_time_zero;
  options.window_s = kHic15Window;
  summary.hic15 = Hic(acc_g, dt, t0, options);
  options.window_s = kHic36Window;
  summary.hic36 = Hic(acc_g, dt, t0, options);
  summary.hic_d = HicD(summary.hic36.value);
  options.window_s = kUnlimitedHicWindow;
  summary.hic = Hic(acc_g, dt, t0, options);
  summary.a3ms_g =
      config.a3ms.definition == A3msDefinition::kContinuous ? A3msContinuous(acc_g, dt) : A3ms(acc_g, dt);
  constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();
  summary.bric = rotation ? Bric(kinematics.omega_body, config.bric.critical_radps) : kUndetermined;
  summary.damage = rotation ? Damage(kinematics.alpha_body, dt) : kUndetermined;
}

}  // namespace napkin::engine
