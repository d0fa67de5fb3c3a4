#pragma once
// Injury risk curves: the probability of a head injury of at least a given
// AIS level that a criterion value stands for (docs/algorithms.md "Injury
// risk", where each curve's form, parameters, source and applicability are).
// Each curve belongs to a summary field of group kRisk, which names it once:
// its field, criterion, AIS level and source (engine/summary_fields.h
// RiskCurve).
//
// A NaN criterion (BrIC of an acceleration-only array) gives a NaN risk; a
// criterion <= 0 gives risk 0 (the curves' limit there).
#include "engine/summary.h"

namespace napkin::engine {

// P(AIS 3+) = Phi((ln HIC15 - mu) / sigma), the head curve of the US NCAP
// frontal rating from model year 2011 (NHTSA, Federal Register 73 (134),
// 11 July 2008, p. 40016 ff.; parameters from Eppinger et al. 1999).
inline constexpr double kNcapHic15Ais3Mu = 7.45231;
inline constexpr double kNcapHic15Ais3Sigma = 0.73998;
double NcapHic15Ais3Risk(double hic15);

// P(AIS 4+) = 1 / (1 + exp(a + b / HIC - c HIC)), the Prasad–Mertz brain
// injury curve (Prasad and Mertz 1985, SAE 851246) of the FMVSS 208 HIC
// (36 ms) era.
inline constexpr double kPrasadMertzA = 4.9;
inline constexpr double kPrasadMertzB = 200.0;
inline constexpr double kPrasadMertzC = 0.00351;
double PrasadMertzHic36Ais4Risk(double hic36);

// P(AIS n+) = 1 - exp(-(BrIC / scale)^shape), Takhounts et al. 2013 (Stapp
// Car Crash Journal 57, 243–266), the curves built on the maximum principal
// strain (MPS) of the SIMon/GHBMC models; they belong to BrIC computed with
// the critical values of that paper (engine/processing.h BricConfig).
inline constexpr double kTakhountsBricShape = 2.84;
inline constexpr double kTakhountsBricAis3Scale = 0.987;
inline constexpr double kTakhountsBricAis4Scale = 1.204;
double TakhountsBricAis3Risk(double bric);
double TakhountsBricAis4Risk(double bric);

// Fills the risk fields of `summary` from their criteria, each by its curve.
void FillInjuryRisks(TestSummary& summary);

}  // namespace napkin::engine
