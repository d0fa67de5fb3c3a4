// ISO/TS 18571 objective rating (docs/algorithms.md "Test against model:
// ISO/TS 18571"); the formulas are the standard's clause 6, the parameters
// its tables, as the public descriptions cited in docs/algorithms.md give them.
#include "engine/iso18571.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"

namespace napkin::engine {
namespace {

constexpr double kIsoInfinity = std::numeric_limits<double>::infinity();
// The fewest samples: the slope score's smoothing spans 9.
constexpr long kIsoMinSamples = 9;

std::string IsoNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

// ((limit - error) / limit)^k, 1 for no error, 0 from the limit on: the
// phase, magnitude and slope scores' shape (clause 6.3).
double IsoScore(double error, double limit, double exponent) {
  if (error <= 0.0) return 1.0;
  if (!(error < limit)) return 0.0;
  return std::pow((limit - error) / limit, exponent);
}

// Pearson's coefficient of x[0..n) and y[0..n) from their sums; NaN when
// either is constant (the coefficient is undefined).
double IsoPearson(double n, double sx, double sy, double sxx, double syy, double sxy) {
  const double cov = sxy - sx * sy / n;
  const double vx = sxx - sx * sx / n;
  const double vy = syy - sy * sy / n;
  if (!(vx > 0.0) || !(vy > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::min(1.0, cov / std::sqrt(vx * vy));
}

// Sum of x[k] y[k], k < n, with four partial sums (the compiler keeps the
// order of one sum, so one accumulator would not vectorise).
double IsoDot(const double* x, const double* y, std::size_t n) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    s0 += x[k] * y[k];
    s1 += x[k + 1] * y[k + 1];
    s2 += x[k + 2] * y[k + 2];
    s3 += x[k + 3] * y[k + 3];
  }
  for (; k < n; ++k) s0 += x[k] * y[k];
  return (s0 + s1) + (s2 + s3);
}

struct IsoPhaseShift {
  long shift = 0;  // > 0: the candidate lags (compare reference[k] with candidate[k + shift])
  double correlation = std::numeric_limits<double>::quiet_NaN();
};

// Clause 6.3.1: the shift of the candidate, by at most floor(max_shift N)
// samples either way, whose overlap with the reference has the largest
// Pearson coefficient; ties keep the smaller shift, and at one shift the
// candidate moved earlier (a lagging candidate). Both curves are centred on
// their means first (the coefficient does not change; the sums below lose
// less to cancellation), then per shift the overlap's sums come from prefix
// sums and one dot product: O(N) per shift.
IsoPhaseShift FindPhaseShift(std::span<const double> reference, std::span<const double> candidate,
                             double max_shift) {
  const std::size_t n = reference.size();
  double mean_r = 0.0, mean_c = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    mean_r += reference[k];
    mean_c += candidate[k];
  }
  mean_r /= static_cast<double>(n);
  mean_c /= static_cast<double>(n);
  std::vector<double> r(n), c(n);
  std::vector<double> pr(n + 1, 0.0), prr(n + 1, 0.0), pc(n + 1, 0.0), pcc(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    r[k] = reference[k] - mean_r;
    c[k] = candidate[k] - mean_c;
    pr[k + 1] = pr[k] + r[k];
    prr[k + 1] = prr[k] + r[k] * r[k];
    pc[k + 1] = pc[k] + c[k];
    pcc[k + 1] = pcc[k] + c[k] * c[k];
  }
  // reference[a, a + len) against candidate[b, b + len).
  auto correlation = [&](std::size_t a, std::size_t b, std::size_t len) {
    return IsoPearson(static_cast<double>(len), pr[a + len] - pr[a], pc[b + len] - pc[b],
                      prr[a + len] - prr[a], pcc[b + len] - pcc[b], IsoDot(r.data() + a, c.data() + b, len));
  };
  IsoPhaseShift best;
  best.correlation = correlation(0, 0, n);
  const auto largest = static_cast<std::size_t>(std::floor(max_shift * static_cast<double>(n) + 1e-9));
  for (std::size_t m = 1; m <= largest && m + 2 <= n; ++m) {
    const double lagging = correlation(0, m, n - m);
    if (lagging > best.correlation || (std::isnan(best.correlation) && !std::isnan(lagging))) {
      best = {static_cast<long>(m), lagging};
    }
    const double leading = correlation(m, 0, n - m);
    if (leading > best.correlation || (std::isnan(best.correlation) && !std::isnan(leading))) {
      best = {-static_cast<long>(m), leading};
    }
  }
  return best;
}

// The band half width of a window fraction over n samples: |i - j| <
// ceil(fraction n), so |i - j| <= ceil(fraction n) - 1.
std::optional<long> BandHalfWidth(const std::optional<double>& fraction, std::size_t n) {
  if (!fraction) return std::nullopt;
  const auto radius = static_cast<long>(std::ceil(*fraction * static_cast<double>(n) - 1e-9));
  return std::max(0L, radius - 1);
}

void CheckIsoCurves(std::span<const double> reference, std::span<const double> candidate, double dt_s) {
  if (reference.size() != candidate.size()) {
    throw InputError("ISO/TS 18571 needs the reference and the candidate on one time base, but they have " +
                     std::to_string(reference.size()) + " and " + std::to_string(candidate.size()) +
                     " samples.");
  }
  if (static_cast<long>(reference.size()) < kIsoMinSamples) {
    throw InputError("ISO/TS 18571 needs at least " + std::to_string(kIsoMinSamples) +
                     " samples in the evaluation interval, but it has " + std::to_string(reference.size()) +
                     ".");
  }
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    throw InputError("ISO/TS 18571 needs a positive sampling interval, not " + IsoNumber(dt_s) + " s.");
  }
  for (std::size_t k = 0; k < reference.size(); ++k) {
    if (!std::isfinite(reference[k]) || !std::isfinite(candidate[k])) {
      throw InputError(std::string("ISO/TS 18571 cannot rate a curve with a non-finite sample: the ") +
                       (std::isfinite(reference[k]) ? "candidate" : "reference") + "'s sample " +
                       std::to_string(k) + " (t = " + IsoNumber(static_cast<double>(k) * dt_s) +
                       " s from the interval's start) is " +
                       IsoNumber(std::isfinite(reference[k]) ? candidate[k] : reference[k]) + ".");
    }
  }
}

}  // namespace

Iso18571Parameters Iso18571Parameters::ForEdition(Iso18571Edition edition) {
  Iso18571Parameters parameters;
  parameters.edition = edition;
  // The 2024 edition fixes the warping window at 10 % of the data length
  // (its foreword); the 2014 text names none, so warping is free.
  parameters.dtw_window = edition == Iso18571Edition::k2014 ? std::nullopt : std::optional<double>(0.1);
  return parameters;
}

void Iso18571Parameters::Check() const {
  auto require = [](bool ok, const char* name, double value, const char* range) {
    if (!ok) {
      throw InputError(std::string("The ISO/TS 18571 parameter ") + name + " is " + IsoNumber(value) +
                       ", but it must be " + range + ".");
    }
  };
  require(a0 >= 0.0 && std::isfinite(a0), "a0", a0, "0 or more");
  require(b0 > a0 && std::isfinite(b0), "b0", b0, "larger than a0");
  require(kz > 0.0 && std::isfinite(kz), "kz", kz, "positive");
  require(max_shift > 0.0 && max_shift < 1.0, "max_shift", max_shift, "between 0 and 1");
  require(kp > 0.0 && std::isfinite(kp), "kp", kp, "positive");
  require(eps_m > 0.0 && std::isfinite(eps_m), "eps_m", eps_m, "positive");
  require(km > 0.0 && std::isfinite(km), "km", km, "positive");
  if (dtw_window) require(*dtw_window > 0.0 && *dtw_window <= 1.0, "dtw_window", *dtw_window, "in (0, 1]");
  require(eps_s > 0.0 && std::isfinite(eps_s), "eps_s", eps_s, "positive");
  require(ks > 0.0 && std::isfinite(ks), "ks", ks, "positive");
  for (const auto& [name, weight] : {std::pair{"w_corridor", w_corridor}, std::pair{"w_phase", w_phase},
                                     std::pair{"w_magnitude", w_magnitude}, std::pair{"w_slope", w_slope}}) {
    require(weight >= 0.0 && weight <= 1.0, name, weight, "between 0 and 1");
  }
  const double sum = w_corridor + w_phase + w_magnitude + w_slope;
  require(std::abs(sum - 1.0) <= 1e-9, "weights' sum", sum, "1");
  require(rate_hz > 0.0 && std::isfinite(rate_hz), "rate_hz", rate_hz, "positive");
}

Iso18571Grade GradeOf(double overall) {
  if (overall > 0.94) return Iso18571Grade::kExcellent;
  if (overall > 0.80) return Iso18571Grade::kGood;
  if (overall > 0.58) return Iso18571Grade::kFair;
  return Iso18571Grade::kPoor;
}

double Iso18571Corridor(std::span<const double> reference, std::span<const double> candidate,
                        const Iso18571Parameters& parameters) {
  double t_norm = 0.0;
  for (double value : reference) t_norm = std::max(t_norm, std::abs(value));
  const double inner = parameters.a0 * t_norm;
  const double outer = parameters.b0 * t_norm;
  double sum = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const double deviation = std::abs(candidate[k] - reference[k]);
    if (deviation <= inner) {
      sum += 1.0;
    } else if (deviation < outer) {
      sum += std::pow((outer - deviation) / (outer - inner), parameters.kz);
    }
  }
  return sum / static_cast<double>(reference.size());
}

// Dynamic time warping in one pass over the band, three anti-diagonals of
// memory: each cell carries, beside its accumulated cost D, the sums
// sum |C - T| and sum |T| along its best path, so the optimal path's sums
// arrive at the last cell without a backtrack (the backtrack would take at
// each cell the predecessor taken here: the same path).
// Order: anti-diagonal by anti-diagonal (s = i + j). A cell's predecessors
// lie on the two previous anti-diagonals, so the cells of one are
// independent: IsoWarpDiagonal has no loop-carried dependency and
// vectorises (engine/CMakeLists.txt: the dynamic vectoriser cost model).
// Pruning (PrunedDTW, Silva and Batista 2016): the unwarped alignment (the
// diagonal) costs UB, and its prefix is a path to each diagonal cell, so the
// optimal path costs at most UB and every cell on it has D <= UB (costs only
// grow along a path, also in floating point). A cell with D > UB is never on
// it nor decides a minimum on it (its successors then exceed UB too), so it
// is set infinite, and an anti-diagonal spans only the cells reachable from
// the survivors of the two before it. Where both curves are flat (a quiet
// stretch before or after an impact) every warping costs alike and nothing
// can be pruned: there the work is the band's.
namespace {

// Anti-diagonal buffers indexed by i + 1 (index 0 and n + 1 are margins).
struct IsoDiagonal {
  std::vector<double> cost, num, den;
  long lo = 0, hi = -1;  // surviving cells (D <= UB): i in [lo, hi], none when hi < lo
  long a = 0, b = -1;    // cells written: i in [a, b]
  explicit IsoDiagonal(long n)
      : cost(static_cast<std::size_t>(n + 2), kIsoInfinity), num(cost.size()), den(cost.size()) {}
  // Makes cost[i] infinite for i in [from, to] outside the written cells.
  void Clear(long from, long to) {
    for (long i = from; i <= std::min(to, a - 1); ++i) cost[static_cast<std::size_t>(i + 1)] = kIsoInfinity;
    for (long i = std::max(from, b + 1); i <= to; ++i) cost[static_cast<std::size_t>(i + 1)] = kIsoInfinity;
  }
};

// Cells i in [from, to] of one anti-diagonal (buffers indexed by i + 1):
// predecessors diagonal (i - 1, j - 1) from `diag` at i, horizontal (i, j - 1)
// from `prev` at i + 1 and vertical (i - 1, j) from `prev` at i; ties prefer
// the diagonal, then the horizontal step (the reference advances), then the
// vertical one. c[i] and t[i] are the candidate and reference samples of
// the cell.
void IsoWarpDiagonal(long from, long to, const double* __restrict dc, const double* __restrict dn,
                     const double* __restrict dd, const double* __restrict pc, const double* __restrict pn,
                     const double* __restrict pd, const double* __restrict c, const double* __restrict t,
                     double upper_bound, double* __restrict oc, double* __restrict on,
                     double* __restrict od) {
  for (long i = from; i <= to; ++i) {
    double best = dc[i], num = dn[i], den = dd[i];
    const double hc = pc[i + 1], hn = pn[i + 1], hd = pd[i + 1];
    const bool h = hc < best;
    best = h ? hc : best;
    num = h ? hn : num;
    den = h ? hd : den;
    const double vc = pc[i], vn = pn[i], vd = pd[i];
    const bool v = vc < best;
    best = v ? vc : best;
    num = v ? vn : num;
    den = v ? vd : den;
    const double d = c[i] - t[i];
    const double total = best + d * d;
    oc[i + 1] = total <= upper_bound ? total : kIsoInfinity;
    on[i + 1] = num + std::fabs(d);
    od[i + 1] = den + std::fabs(t[i]);
  }
}

}  // namespace

double Iso18571MagnitudeError(std::span<const double> reference, std::span<const double> candidate,
                              std::optional<long> window) {
  const long n = static_cast<long>(reference.size());
  const long w = window ? std::min(*window, n - 1) : n - 1;
  double upper_bound = 0.0;
  for (long k = 0; k < n; ++k) {
    const double d = candidate[k] - reference[k];
    upper_bound += d * d;
  }
  // The reference reversed, so T(s - i) = reversed[n - 1 - s + i] runs forward with i.
  const std::vector<double> reversed(reference.rbegin(), reference.rend());
  IsoDiagonal d0(n), d1(n), d2(n);  // s, s - 1, s - 2
  {
    // s = 0: the cell (0, 0).
    const double d = candidate[0] - reference[0];
    d1.cost[1] = d * d;
    d1.num[1] = std::abs(d);
    d1.den[1] = std::abs(reference[0]);
    d1.a = d1.b = d1.lo = d1.hi = 0;
  }
  for (long s = 1; s <= 2 * (n - 1); ++s) {
    // The band |2 i - s| <= w, and the cells reachable from the survivors of
    // s - 1 (at i and i - 1) and s - 2 (at i - 1).
    long from = std::max({0L, s - (n - 1), s - w > 0 ? (s - w + 1) / 2 : 0L});
    long to = std::min({n - 1, s, (s + w) / 2});
    long reach_from = n, reach_to = -1;
    if (d1.hi >= d1.lo) {
      reach_from = std::min(reach_from, d1.lo);
      reach_to = std::max(reach_to, d1.hi + 1);
    }
    if (d2.hi >= d2.lo) {
      reach_from = std::min(reach_from, d2.lo + 1);
      reach_to = std::max(reach_to, d2.hi + 1);
    }
    from = std::max(from, reach_from);
    to = std::min(to, reach_to);
    d1.Clear(from - 1, to);
    d2.Clear(from - 1, to - 1);
    IsoWarpDiagonal(from, to, d2.cost.data(), d2.num.data(), d2.den.data(), d1.cost.data(), d1.num.data(),
                    d1.den.data(), candidate.data(), reversed.data() + (n - 1 - s), upper_bound,
                    d0.cost.data(), d0.num.data(), d0.den.data());
    d0.a = d0.lo = from;
    d0.b = d0.hi = to;
    const double* cost = d0.cost.data() + 1;
    while (d0.lo <= d0.hi && !(cost[d0.lo] <= upper_bound)) ++d0.lo;
    while (d0.hi >= d0.lo && !(cost[d0.hi] <= upper_bound)) --d0.hi;
    std::swap(d2, d1);  // d2: s - 1
    std::swap(d1, d0);  // d1: s; d0: free for s + 1
  }
  // The last anti-diagonal, s = 2 (n - 1), is the cell (n - 1, n - 1) alone.
  const double num = d1.num[static_cast<std::size_t>(n)];
  const double den = d1.den[static_cast<std::size_t>(n)];
  if (den == 0.0) return num == 0.0 ? 0.0 : kIsoInfinity;
  return num / den;
}

double Iso18571MagnitudeErrorFullMatrix(std::span<const double> reference, std::span<const double> candidate,
                                        std::optional<long> window) {
  const long n = static_cast<long>(reference.size());
  const long w = window ? std::min(*window, n - 1) : n - 1;
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(n, n, kIsoInfinity);
  auto at = [&](long i, long j) { return i < 0 || j < 0 ? kIsoInfinity : cost(i, j); };
  for (long i = 0; i < n; ++i) {
    for (long j = std::max(0L, i - w); j <= std::min(n - 1, i + w); ++j) {
      const double d = candidate[i] - reference[j];
      const double best = i == 0 && j == 0 ? 0.0 : std::min({at(i - 1, j - 1), at(i, j - 1), at(i - 1, j)});
      cost(i, j) = best + d * d;
    }
  }
  double num = 0.0, den = 0.0;
  long i = n - 1, j = n - 1;
  while (true) {
    num += std::abs(candidate[i] - reference[j]);
    den += std::abs(reference[j]);
    if (i == 0 && j == 0) break;
    // The predecessor the forward pass takes: diagonal, horizontal, vertical.
    long bi = i - 1, bj = j - 1;
    double best = at(i - 1, j - 1);
    if (at(i, j - 1) < best) {
      best = at(i, j - 1);
      bi = i;
      bj = j - 1;
    }
    if (at(i - 1, j) < best) {
      bi = i - 1;
      bj = j;
    }
    i = bi;
    j = bj;
  }
  if (den == 0.0) return num == 0.0 ? 0.0 : kIsoInfinity;
  return num / den;
}

Eigen::VectorXd Iso18571SmoothedDerivative(std::span<const double> values, double dt_s) {
  const auto n = static_cast<Eigen::Index>(values.size());
  Eigen::VectorXd raw(n);
  if (n == 1) raw(0) = 0.0;
  for (Eigen::Index k = 0; k < n && n > 1; ++k) {
    if (k == 0) {
      raw(k) = (values[1] - values[0]) / dt_s;
    } else if (k == n - 1) {
      raw(k) = (values[k] - values[k - 1]) / dt_s;
    } else {
      raw(k) = (values[k + 1] - values[k - 1]) / (2.0 * dt_s);
    }
  }
  Eigen::VectorXd smooth(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    // Half width 4, narrowed near the ends so the average stays centred.
    const Eigen::Index half = std::min<Eigen::Index>({4, k, n - 1 - k});
    smooth(k) = raw.segment(k - half, 2 * half + 1).sum() / static_cast<double>(2 * half + 1);
  }
  return smooth;
}

Iso18571Rating Iso18571Rate(std::span<const double> reference, std::span<const double> candidate, double dt_s,
                            const Iso18571Parameters& parameters) {
  parameters.Check();
  CheckIsoCurves(reference, candidate, dt_s);
  const auto n = static_cast<long>(reference.size());
  Iso18571Rating rating;
  rating.samples = n;
  double t_norm = 0.0;
  for (double value : reference) t_norm = std::max(t_norm, std::abs(value));
  if (t_norm == 0.0) {
    throw InputError(
        "ISO/TS 18571 cannot rate against a reference that is zero throughout the evaluation interval (its "
        "corridors are fractions of the reference's largest magnitude).");
  }
  rating.inner_half_width = parameters.a0 * t_norm;
  rating.outer_half_width = parameters.b0 * t_norm;

  // Clause 6.2: the corridor score, on the whole interval.
  rating.corridor = Iso18571Corridor(reference, candidate, parameters);

  // Clause 6.3.1: the phase score from the best shift.
  const IsoPhaseShift shift = FindPhaseShift(reference, candidate, parameters.max_shift);
  rating.shift_samples = shift.shift;
  rating.shift_s = static_cast<double>(shift.shift) * dt_s;
  rating.correlation = shift.correlation;
  const double allowed = parameters.max_shift * static_cast<double>(n);
  rating.phase = IsoScore(static_cast<double>(std::abs(shift.shift)) / allowed, 1.0, parameters.kp);

  // Clauses 6.3.2 and 6.3.3 compare the shifted curves: their overlap.
  const auto m = static_cast<std::size_t>(std::abs(shift.shift));
  const std::size_t overlap = reference.size() - m;
  const std::span<const double> t_shifted =
      shift.shift >= 0 ? reference.first(overlap) : reference.subspan(m);
  const std::span<const double> c_shifted =
      shift.shift >= 0 ? candidate.subspan(m) : candidate.first(overlap);

  rating.magnitude_error =
      Iso18571MagnitudeError(t_shifted, c_shifted, BandHalfWidth(parameters.dtw_window, overlap));
  rating.magnitude = IsoScore(rating.magnitude_error, parameters.eps_m, parameters.km);

  const Eigen::VectorXd t_slope = Iso18571SmoothedDerivative(t_shifted, dt_s);
  const Eigen::VectorXd c_slope = Iso18571SmoothedDerivative(c_shifted, dt_s);
  const double slope_num = (c_slope - t_slope).cwiseAbs().sum();
  const double slope_den = t_slope.cwiseAbs().sum();
  rating.slope_error = slope_den == 0.0 ? (slope_num == 0.0 ? 0.0 : kIsoInfinity) : slope_num / slope_den;
  rating.slope = IsoScore(rating.slope_error, parameters.eps_s, parameters.ks);

  // Clause 6.1: the overall rating; clause 7: its grade.
  rating.overall = parameters.w_corridor * rating.corridor + parameters.w_phase * rating.phase +
                   parameters.w_magnitude * rating.magnitude + parameters.w_slope * rating.slope;
  rating.grade = GradeOf(rating.overall);
  return rating;
}

Eigen::VectorXd Iso18571TimeBase(double start_s, double end_s, double rate_hz) {
  const double dt_s = 1.0 / rate_hz;
  const auto count = static_cast<Eigen::Index>(std::floor((end_s - start_s) * rate_hz + 1e-6)) + 1;
  Eigen::VectorXd base(std::max<Eigen::Index>(count, 0));
  for (Eigen::Index k = 0; k < base.size(); ++k) base(k) = start_s + static_cast<double>(k) * dt_s;
  return base;
}

Iso18571Rating Iso18571RateCurves(const TimeSeries& reference, const TimeSeries& candidate,
                                  const Iso18571Interval& interval, const Iso18571Parameters& parameters,
                                  std::string_view reference_name, std::string_view candidate_name) {
  parameters.Check();
  const double dt_s = 1.0 / parameters.rate_hz;
  for (const auto& [series, name] :
       {std::pair{&reference, reference_name}, std::pair{&candidate, candidate_name}}) {
    const Eigen::Index n = std::min(series->time_s.size(), series->values.size());
    if (n < 2) throw InputError(std::string(name) + " has fewer than 2 samples.");
    for (Eigen::Index k = 1; k < n; ++k) {
      if (!(series->time_s(k) > series->time_s(k - 1))) {
        throw InputError(std::string(name) + "'s sample times do not increase at sample " +
                         std::to_string(k) + " (t = " + IsoNumber(series->time_s(k)) + " s).");
      }
    }
  }
  auto first = [](const TimeSeries& s) { return s.time_s(0); };
  auto last = [](const TimeSeries& s) { return s.time_s(std::min(s.time_s.size(), s.values.size()) - 1); };
  const double start = interval.start_s.value_or(std::max(first(reference), first(candidate)));
  const double end = interval.end_s.value_or(std::min(last(reference), last(candidate)));
  const double tolerance = 1e-9 * dt_s;
  if (!(end > start)) {
    throw InputError("The ISO/TS 18571 evaluation interval from " + IsoNumber(start) + " s to " +
                     IsoNumber(end) + " s is empty.");
  }
  for (const auto& [series, name] :
       {std::pair{&reference, reference_name}, std::pair{&candidate, candidate_name}}) {
    if (start < first(*series) - tolerance || end > last(*series) + tolerance) {
      throw InputError("The ISO/TS 18571 evaluation interval from " + IsoNumber(start) + " s to " +
                       IsoNumber(end) + " s reaches outside " + std::string(name) + " (" +
                       IsoNumber(first(*series)) + " s to " + IsoNumber(last(*series)) + " s).");
    }
  }
  const Eigen::VectorXd base = Iso18571TimeBase(start, end, parameters.rate_hz);
  const Eigen::VectorXd t = ResampleOnto(reference, base);
  const Eigen::VectorXd c = ResampleOnto(candidate, base);
  return Iso18571Rate(std::span<const double>(t.data(), static_cast<std::size_t>(t.size())),
                      std::span<const double>(c.data(), static_cast<std::size_t>(c.size())), dt_s,
                      parameters);
}

}  // namespace napkin::engine
