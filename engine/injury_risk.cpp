#include "engine/injury_risk.h"

#include <boost/math/distributions/normal.hpp>
#include <cmath>

namespace napkin::engine {
namespace {

// The curves are probabilities of a non-negative criterion: at or below 0
// every one of them is 0 (their limit), and a NaN stays NaN.
bool AtOrBelowZero(double criterion) { return criterion <= 0.0; }

constexpr InjuryRiskCurve kCurves[] = {
    {"hic15_p_ais3", "hic15", 3, NcapHic15Ais3Risk},
    {"hic36_p_ais4", "hic36", 4, PrasadMertzHic36Ais4Risk},
    {"bric_p_ais3", "bric", 3, TakhountsBricAis3Risk},
    {"bric_p_ais4", "bric", 4, TakhountsBricAis4Risk},
};

double Weibull(double x, double scale, double shape) {
  if (std::isnan(x)) return x;
  if (AtOrBelowZero(x)) return 0.0;
  return -std::expm1(-std::pow(x / scale, shape));
}

}  // namespace

double NcapHic15Ais3Risk(double hic15) {
  if (std::isnan(hic15)) return hic15;
  if (AtOrBelowZero(hic15)) return 0.0;
  const boost::math::normal standard_normal(0.0, 1.0);
  return boost::math::cdf(standard_normal, (std::log(hic15) - kNcapHic15Ais3Mu) / kNcapHic15Ais3Sigma);
}

double PrasadMertzHic36Ais4Risk(double hic36) {
  if (std::isnan(hic36)) return hic36;
  if (AtOrBelowZero(hic36)) return 0.0;
  return 1.0 / (1.0 + std::exp(kPrasadMertzA + kPrasadMertzB / hic36 - kPrasadMertzC * hic36));
}

double TakhountsBricAis3Risk(double bric) {
  return Weibull(bric, kTakhountsBricAis3Scale, kTakhountsBricShape);
}

double TakhountsBricAis4Risk(double bric) {
  return Weibull(bric, kTakhountsBricAis4Scale, kTakhountsBricShape);
}

std::span<const InjuryRiskCurve> InjuryRiskCurves() { return kCurves; }

const InjuryRiskCurve* FindInjuryRiskCurve(std::string_view field) {
  for (const InjuryRiskCurve& curve : kCurves)
    if (field == curve.field) return &curve;
  return nullptr;
}

void FillInjuryRisks(TestSummary& summary) {
  summary.hic15_p_ais3 = NcapHic15Ais3Risk(summary.hic15.value);
  summary.hic36_p_ais4 = PrasadMertzHic36Ais4Risk(summary.hic36.value);
  summary.bric_p_ais3 = TakhountsBricAis3Risk(summary.bric);
  summary.bric_p_ais4 = TakhountsBricAis4Risk(summary.bric);
}

}  // namespace napkin::engine
