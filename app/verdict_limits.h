#pragma once
// The verdict's words about limits (docs/formats.md "Verdict", "Limits"):
// per limit set, a column of the verdict's table and a clause of each
// variant's sentence, from `napkin compare`'s checks (app/comparison.h):
// how many tests meet a maximum, the points of a sliding scale and of the
// combined head, the tests per band, and what a further test would give.
// Kept apart from app/verdict.cpp, which words the comparisons.
#include <cstddef>
#include <string>
#include <vector>

#include "app/comparison.h"

namespace napkin::app {

// The verdict table's columns of set `s`: "meet NAME" (its maximum limits),
// "NAME head points" (its combined region) or "NAME HIC15 points" (a scale
// without one), "NAME HIC15" (bands).
std::vector<std::string> LimitSetColumns(const Comparison& comparison, std::size_t s);

// Group g's cells under those columns: "4 of 5", "2.1 of 4", "3 Good, 2 Acceptable" ("—" without tests).
std::vector<std::string> LimitSetCells(const Comparison& comparison, std::size_t s, std::size_t g);

// Group g's clause about set `s`: its tests against the maximum limits
// ("all 5 foam-b tests meet FMVSS 201U (highest HIC(d) 562.7, margin 44 %)"),
// the points of the scales and the combined region, the tests per band, and
// a further test: "a further test exceeds HIC(d) 1000 with probability
// 0.3 %", "scores HIC15 2.1 points expected [0.4, 3.5] (80 % prediction
// interval)", or why it is not estimated.
std::string LimitSetClause(const Comparison& comparison, std::size_t s, std::size_t g);

// What the clauses of set `s` mean, for the report's note.
std::string LimitSetNote(const Comparison& comparison, std::size_t s);

// "0.3 %": a probability in % (two significant digits; "< 0.0001 %" below 1e-6, "> 99.9999 %" above).
std::string FurtherProbabilityText(double p);

}  // namespace napkin::app
