// HIC, its window and HIC(d) (engine/hic.h; docs/algorithms.md "Injury criteria").
#include "engine/hic.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/criterion_checks.h"

namespace napkin::engine {

using internal::CheckFiniteSamples;
using internal::CheckInterval;

namespace {

// The samples HIC works on, with their cumulative trapezoid integral.
struct HicProblem {
  Eigen::Index first = 0;      // index (in the input) of the first sample used
  Eigen::Index count = 0;      // number of samples used
  Eigen::Index max_steps = 0;  // longest window, in sampling intervals
  Eigen::VectorXd integral;    // V_k, k = 0..count-1 (g s)
};

void CheckHicWindow(double window_s) {
  if (std::isnan(window_s) || !(window_s > 0.0)) {
    std::ostringstream message;
    message << "HIC: the window " << window_s << " s is not positive.";
    throw InputError(message.str());
  }
}

// The longest window, in sampling intervals, of `count` samples.
Eigen::Index HicMaxSteps(double window_s, double dt_s, Eigen::Index count) {
  const Eigen::Index longest = std::max<Eigen::Index>(count - 1, 0);
  if (std::isinf(window_s)) return longest;
  // Windows of exactly W are included; W / dt is rarely an exact double.
  const double steps = std::floor(window_s / dt_s * (1.0 + 1e-9));
  return steps >= static_cast<double>(longest) ? longest : static_cast<Eigen::Index>(steps);
}

// `storage`: memory for the integral kept from an earlier problem (no new
// pages when it is as long; HicWork).
HicProblem PrepareHic(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                      const HicOptions& options, Eigen::VectorXd storage = {}) {
  CheckInterval(dt_s, "HIC");
  if (!std::isfinite(t0_s)) throw InputError("HIC: the time of the first sample is not finite.");
  CheckHicWindow(options.window_s);
  CheckFiniteSamples(acc_g, dt_s, t0_s, "HIC");
  HicProblem problem;
  problem.integral = std::move(storage);
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
  problem.max_steps = HicMaxSteps(options.window_s, dt_s, problem.count);
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

// Segment tree over sample indices, leaves padded to a power of two: node h
// (root 1, children 2h and 2h + 1) covers samples [lo, hi]; max_integral and
// min_integral = max and min of V over them, max_step = max of the steps
// V_{k+1} - V_k with both k and k + 1 inside (-inf for a single sample).
struct HicSegmentTree {
  Eigen::Index leaves = 0;
  std::vector<double> max_integral;
  std::vector<double> min_integral;
  std::vector<double> max_step;
};

// `tree`: an earlier tree whose vectors are reused (assign keeps their capacity).
// `cancel` is looked at between the passes (never inside one, which stays a
// plain loop): filling three arrays of twice the samples' count takes a few
// tenths of a second for a long record the first time (fresh memory).
HicSegmentTree BuildHicSegmentTree(const double* integral, Eigen::Index count, HicSegmentTree tree = {},
                                   const std::atomic<bool>* cancel = nullptr) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto leaves = static_cast<Eigen::Index>(std::bit_ceil(static_cast<std::size_t>(count)));
  tree.leaves = leaves;
  tree.max_integral.assign(static_cast<std::size_t>(2 * leaves), -kInf);
  ThrowIfCancelled(cancel);
  tree.min_integral.assign(static_cast<std::size_t>(2 * leaves), kInf);
  ThrowIfCancelled(cancel);
  tree.max_step.assign(static_cast<std::size_t>(2 * leaves), -kInf);
  ThrowIfCancelled(cancel);
  for (Eigen::Index k = 0; k < count; ++k) {
    tree.max_integral[static_cast<std::size_t>(leaves + k)] = integral[k];
    tree.min_integral[static_cast<std::size_t>(leaves + k)] = integral[k];
  }
  for (Eigen::Index width = 2, first_node = leaves / 2; first_node >= 1; width *= 2, first_node /= 2) {
    ThrowIfCancelled(cancel);
    for (Eigen::Index h = first_node; h < 2 * first_node; ++h) {
      const auto node = static_cast<std::size_t>(h), left = 2 * node, right = left + 1;
      // The step across the children's boundary: sample `boundary` to boundary + 1.
      const Eigen::Index boundary = (h - first_node) * width + width / 2 - 1;
      const double boundary_step = boundary + 1 < count ? integral[boundary + 1] - integral[boundary] : -kInf;
      tree.max_integral[node] = std::max(tree.max_integral[left], tree.max_integral[right]);
      tree.min_integral[node] = std::min(tree.min_integral[left], tree.min_integral[right]);
      tree.max_step[node] = std::max({tree.max_step[left], tree.max_step[right], boundary_step});
    }
  }
  return tree;
}

// Relative rounding slack on sums of steps of V (a few ulp, generously).
constexpr double kHicRoundingSlack = 8.0 * std::numeric_limits<double>::epsilon();

// Largest |V_{k+1} - V_k|: the scale of the rounding slack on integrals.
double MaxAbsStep(const double* integral, Eigen::Index count) {
  double max_abs_step = 0.0;
  for (Eigen::Index k = 0; k + 1 < count; ++k)
    max_abs_step = std::max(max_abs_step, std::abs(integral[k + 1] - integral[k]));
  return max_abs_step;
}

// "Could a window of duration d (steps) and integral `area` beat, or tie,
// the best so far?" HIC = d dt (I / (d dt))^2.5 > best  <=>
// I > best^0.4 (d dt)^0.6  <=>  I^5 > best^2 (d dt)^3 (I > 0): no power
// function on the search's path. A 1e-9 relative margin covers the
// rounding of both sides (a few ulp), so a window that ties is never
// rejected; the exact value decides (HicValue).
class HicThreshold {
 public:
  explicit HicThreshold(double dt_s) : dt_s_(dt_s) {}

  void SetBest(double best_value) {
    best_value_ = best_value;
    const double dt3 = dt_s_ * dt_s_ * dt_s_;
    scale_ = best_value * best_value * dt3 * kMarginFifth;
    // best^2 dt^3 can underflow (or overflow) for extreme units: compare
    // with the power functions then.
    use_power_functions_ = best_value > 0.0 && !(scale_ > std::numeric_limits<double>::min() &&
                                                 std::isfinite(scale_) && scale_ < 1e200);
  }

  bool MayBeat(double area, Eigen::Index steps) const {
    if (!(area > 0.0)) return false;
    if (best_value_ <= 0.0) return true;
    const auto d = static_cast<double>(steps);
    if (!use_power_functions_) {
      const double area5 = area * area * area * area * area;
      if (area5 > std::numeric_limits<double>::min() && area5 < 1e300) return area5 > scale_ * (d * d * d);
    }
    return area > std::pow(best_value_, 0.4) * kMargin * std::pow(d * dt_s_, 0.6);
  }

 private:
  static constexpr double kMargin = 1.0 - 1e-9;
  static constexpr double kMarginFifth = 1.0 - 5e-9;
  double dt_s_;
  double best_value_ = 0.0;
  double scale_ = 0.0;
  bool use_power_functions_ = false;
};

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

// Branch and bound over pairs of blocks (docs/algorithms.md "Injury
// criteria"). A pair (P, Q) of tree nodes of one level holds the windows
// with t1 in P and t2 in Q (t1 < t2). When P lies before Q, with b the last
// sample of P and c the first of Q, every window of the pair has duration
// d in [c - b, last of Q - first of P] and an integral I = V_j - V_i with
//   (M) I <= max V over Q - min V over P, and
//   (L) I <= (V_c - V_b) + (d - (c - b)) m, m = the largest step of V inside
//       P or Q (V_j - V_c <= (j - c) m and V_b - V_i <= (b - i) m).
// (When P = Q, I <= d m and (M) hold with d >= 1.) The bound
// B(d) = min(L(d), M) gives HIC <= B(d)^2.5 / (d dt)^1.5, which is largest
// at the shortest d or where L reaches M: on the linear part
// d/dd log(L^2.5 / d^1.5) = 2.5 m / L - 1.5 / d changes sign at most once,
// from - to +, and beyond it the bound decreases. Testing those two
// durations (HicThreshold) bounds every window of the pair; the linear
// bound carries an absolute rounding slack. Pairs that may hold a better
// window are split into their four (three when P = Q) child pairs, the most
// promising first (largest (M)^5 / (shortest d)^3), so a good window is
// found early and prunes the rest. Windows of single samples are valued by
// HicValue, as the exhaustive search does, and compared with its tie rule
// (a total order), so the result is the exhaustive one, bit for bit, in
// whatever order the windows are visited.
namespace {

// The search itself, over windows of up to `max_steps` intervals, from
// `seed`: a window of that length or shorter (its value from HicValue), or
// none (HicBest{}). A seed only raises the first threshold: the best
// window is the same, since every window that could beat or tie it is still
// visited.
HicBest SearchHic(const HicProblem& problem, const HicSegmentTree& tree, double max_abs_step,
                  Eigen::Index max_steps, double dt_s, const HicBest& seed,
                  const std::atomic<bool>* cancel = nullptr) {
  const Eigen::Index count = problem.count;
  HicBest best = seed;
  if (count < 2) return best;
  const double* integral = problem.integral.data();
  const double slack_per_step = kHicRoundingSlack * max_abs_step;
  HicThreshold threshold(dt_s);
  if (best.i >= 0) threshold.SetBest(best.value);

  // A pair of nodes p <= q of one level, `width` samples each, first
  // samples p_lo and q_lo.
  struct BlockPair {
    Eigen::Index p, q, p_lo, q_lo, width;
  };
  // May some window of the pair beat the best? (Its durations clipped to
  // the window limit and the record.)
  const auto may_beat = [&](const BlockPair& pair) -> bool {
    const auto p = static_cast<std::size_t>(pair.p), q = static_cast<std::size_t>(pair.q);
    const Eigen::Index p_hi = std::min(pair.p_lo + pair.width - 1, count - 1);
    const Eigen::Index q_hi = std::min(pair.q_lo + pair.width - 1, count - 1);
    const double largest = tree.max_integral[q] - tree.min_integral[p];  // (M)
    if (!(largest > 0.0)) return false;
    Eigen::Index shortest, longest;
    double linear_at_shortest, slope;
    if (pair.p == pair.q) {
      shortest = 1;
      longest = q_hi - pair.p_lo;
      slope = tree.max_step[p];
      linear_at_shortest = slope;
    } else {
      shortest = pair.q_lo - p_hi;
      longest = q_hi - pair.p_lo;
      slope = std::max(tree.max_step[p], tree.max_step[q]);
      linear_at_shortest = integral[pair.q_lo] - integral[p_hi];
    }
    if (shortest > max_steps) return false;
    longest = std::min(longest, max_steps);
    const auto span = static_cast<double>(longest - shortest);
    const double slack =
        kHicRoundingSlack * std::abs(linear_at_shortest) + slack_per_step * static_cast<double>(longest);
    if (threshold.MayBeat(std::min(linear_at_shortest + slack, largest), shortest)) return true;
    if (!(slope > 0.0) || linear_at_shortest + slack >= largest || span == 0.0) return false;
    // Where L meets M (or the longest duration): the threshold grows with d,
    // so rounding the duration down keeps the test conservative.
    const double meet = (largest - linear_at_shortest - slack) / slope;
    if (meet >= span)
      return threshold.MayBeat(std::min(linear_at_shortest + span * slope + slack, largest), longest);
    return threshold.MayBeat(largest, shortest + static_cast<Eigen::Index>(meet));
  };
  // Ordering heuristic only (no bound): (M)^5 / (shortest d)^3.
  const auto promise = [&](const BlockPair& pair) -> double {
    const double largest = tree.max_integral[static_cast<std::size_t>(pair.q)] -
                           tree.min_integral[static_cast<std::size_t>(pair.p)];
    if (!(largest > 0.0)) return -1.0;
    const auto shortest =
        static_cast<double>(pair.p == pair.q ? 1 : pair.q_lo - (pair.p_lo + pair.width - 1));
    const double largest_sq = largest * largest;
    return largest_sq * largest_sq * largest / (shortest * shortest * shortest);
  };

  std::vector<BlockPair> stack;
  stack.reserve(256);
  stack.push_back({1, 1, 0, 0, tree.leaves});
  for (Eigen::Index visited = 0; !stack.empty(); ++visited) {
    ThrowIfCancelled(cancel, visited);
    const BlockPair pair = stack.back();
    stack.pop_back();
    if (pair.q_lo >= count) continue;
    if (pair.width == 1) {  // the window (p_lo, q_lo), p_lo < q_lo
      const Eigen::Index i = pair.p_lo, j = pair.q_lo;
      if (j - i > max_steps) continue;
      const double area = integral[j] - integral[i];
      if (!threshold.MayBeat(area, j - i)) continue;
      const double value = HicValue(integral, i, j, dt_s);
      if (best.IsBeatenBy(value, i, j)) {
        best = {value, i, j};
        threshold.SetBest(value);
      }
      continue;
    }
    if (!may_beat(pair)) continue;
    const Eigen::Index half = pair.width / 2;
    std::array<BlockPair, 4> children;
    std::size_t child_count = 0;
    const Eigen::Index pl = 2 * pair.p, pr = pl + 1, ql = 2 * pair.q, qr = ql + 1;
    if (pair.p == pair.q) {
      children[child_count++] = {pl, pl, pair.p_lo, pair.p_lo, half};
      children[child_count++] = {pl, qr, pair.p_lo, pair.q_lo + half, half};
      children[child_count++] = {pr, qr, pair.p_lo + half, pair.q_lo + half, half};
    } else {
      children[child_count++] = {pl, ql, pair.p_lo, pair.q_lo, half};
      children[child_count++] = {pl, qr, pair.p_lo, pair.q_lo + half, half};
      children[child_count++] = {pr, ql, pair.p_lo + half, pair.q_lo, half};
      children[child_count++] = {pr, qr, pair.p_lo + half, pair.q_lo + half, half};
    }
    std::array<double, 4> scores{};
    for (std::size_t c = 0; c < child_count; ++c) scores[c] = promise(children[c]);
    // Push in increasing promise, so the most promising pair is popped first.
    std::array<std::size_t, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(child_count),
              [&](std::size_t a, std::size_t b) { return scores[a] < scores[b]; });
    for (std::size_t c = 0; c < child_count; ++c)
      if (scores[order[c]] > 0.0) stack.push_back(children[order[c]]);
  }
  return best;
}

}  // namespace

HicWindow Hic(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
              const HicOptions& options) {
  const HicProblem problem = PrepareHic(acc_g, dt_s, t0_s, options);
  if (problem.count < 2) return MakeHicWindow(problem, HicBest{}, dt_s, t0_s);
  const double* integral = problem.integral.data();
  const HicSegmentTree tree = BuildHicSegmentTree(integral, problem.count);
  const HicBest best =
      SearchHic(problem, tree, MaxAbsStep(integral, problem.count), problem.max_steps, dt_s, HicBest{});
  return MakeHicWindow(problem, best, dt_s, t0_s);
}

std::vector<HicWindow> HicForWindows(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                                     const std::vector<double>& windows_s, bool from_time_zero,
                                     const std::atomic<bool>* cancel, HicWork& work) {
  for (const double window_s : windows_s) CheckHicWindow(window_s);
  HicOptions options;
  options.from_time_zero = from_time_zero;
  HicProblem problem = PrepareHic(acc_g, dt_s, t0_s, options, std::move(work.integral));
  std::vector<HicWindow> windows(windows_s.size());
  if (problem.count < 2) {
    for (HicWindow& window : windows) window = MakeHicWindow(problem, HicBest{}, dt_s, t0_s);
    work.integral = std::move(problem.integral);
    return windows;
  }
  const double* integral = problem.integral.data();
  ThrowIfCancelled(cancel);
  HicSegmentTree tree = BuildHicSegmentTree(
      integral, problem.count,
      {0, std::move(work.max_integral), std::move(work.min_integral), std::move(work.max_step)}, cancel);
  const double max_abs_step = MaxAbsStep(integral, problem.count);
  // Shortest limit first: its best window is a window of every longer limit.
  std::vector<std::size_t> order(windows_s.size());
  for (std::size_t w = 0; w < order.size(); ++w) order[w] = w;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return windows_s[a] < windows_s[b]; });
  HicBest seed;
  for (const std::size_t w : order) {
    const Eigen::Index max_steps = HicMaxSteps(windows_s[w], dt_s, problem.count);
    if (seed.i >= 0 && seed.j - seed.i > max_steps) seed = HicBest{};
    ThrowIfCancelled(cancel);
    seed = SearchHic(problem, tree, max_abs_step, max_steps, dt_s, seed, cancel);
    windows[w] = MakeHicWindow(problem, seed, dt_s, t0_s);
  }
  work.integral = std::move(problem.integral);
  work.max_integral = std::move(tree.max_integral);
  work.min_integral = std::move(tree.min_integral);
  work.max_step = std::move(tree.max_step);
  return windows;
}

std::vector<HicWindow> HicForWindows(const Eigen::Ref<const Eigen::VectorXd>& acc_g, double dt_s, double t0_s,
                                     const std::vector<double>& windows_s, bool from_time_zero,
                                     const std::atomic<bool>* cancel) {
  HicWork work;
  return HicForWindows(acc_g, dt_s, t0_s, windows_s, from_time_zero, cancel, work);
}

}  // namespace napkin::engine
