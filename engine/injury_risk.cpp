#include "engine/injury_risk.h"

#include <boost/math/distributions/normal.hpp>
#include <cmath>

#include "engine/summary_fields.h"

namespace napkin::engine {
namespace {

// The curves are probabilities of a non-negative criterion: at or below 0
// every one of them is 0 (their limit), and a NaN stays NaN.
bool AtOrBelowZero(double criterion) { return criterion <= 0.0; }

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

void FillInjuryRisks(TestSummary& summary) {
  for (const SummaryField* field : RiskFields())
    field->Set(summary, field->curve->risk(FindSummaryField(field->curve->criterion)->Get(summary)));
}

}  // namespace napkin::engine
