#pragma once
// The one list of a test's numeric summary fields (docs/formats.md "Per-test
// summary fields"): their query-contract names, order and query group, their
// labels and units, and for each injury risk its curve. The results table and
// the views of schema/, the summary JSON, the catalogue's column lists and
// summary equality follow it, and so do the labels of the HTML report, the
// verdict and the Python module; tests/db/schema_test.cpp proves that the
// schema agrees with it.
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/summary.h"

namespace napkin::engine {

// Which `napkin query` view shows a field; `query criteria` shows both.
enum class SummaryGroup {
  kHic,       // query hic (and criteria)
  kRotation,  // query rotation (and criteria)
  kRisk,      // query risk: injury risks (engine/injury_risk.h)
  kQuality,   // stored with the result, shown by no view and not in the JSON
};

// The curve an injury risk is computed with (engine/injury_risk.h,
// docs/algorithms.md "Injury risk").
struct RiskCurve {
  const char* criterion;  // the summary field it reads, e.g. "hic15"
  int ais;                // the risk is P(AIS >= ais)
  const char* source;     // its source in a word or two, e.g. "NCAP"
  double (*risk)(double criterion);
};

struct SummaryField {
  const char* name;  // column name of the query contract
  SummaryGroup group;
  // Short, for sentences and tables ("HIC15", "peak acceleration"); a risk's
  // is made from its curve (FieldLabel).
  const char* label;
  const char* unit;     // "g", "rad/s", ...; "" for a number without unit
  const char* meaning;  // one line, with the unit
  // The field in a summary, or nullptr for a criterion the row computes
  // (compute below), whose value lives in TestSummary::computed under the
  // field's name. Get and Set go through it.
  double& (*field)(TestSummary&);
  // A risk's curve; nullptr for every other field.
  const RiskCurve* curve = nullptr;
  // What a table adds to the label besides the unit ("no window limit").
  const char* detail = "";
  // Compared on the log scale by `napkin compare --scale log` (app/comparison.cpp,
  // docs/algorithms.md "Comparison"): a positive, right-skewed criterion whose
  // groups differ by a ratio.
  bool log_scale = false;
  // One of the criteria the verdict reads (app/verdict.cpp), with the risks
  // computed from it.
  bool in_verdict = false;
  // A criterion of the kinematics alone, computed by FillCriteria
  // (engine/criteria.h) into TestSummary::computed: a new criterion is its
  // engine function and this row (docs/developing.md "Adding a criterion").
  // nullptr for the fields FillCriteria and SummarizeKinematics fill by name.
  double (*compute)(const Kinematics&) = nullptr;

  double Get(const TestSummary& summary) const {
    if (field == nullptr) {
      const auto found = summary.computed.find(std::string_view(name));
      return found != summary.computed.end() ? found->second : 0.0;  // 0.0, as every member starts
    }
    return field(const_cast<TestSummary&>(summary));  // the accessor only forms a reference
  }
  void Set(TestSummary& summary, double value) const {
    if (field == nullptr)
      summary.computed.insert_or_assign(name, value);
    else
      field(summary) = value;
  }
};

// Every numeric field, in the order of the results table's columns (fields
// added by later schema versions come last, as their columns do; the table's
// napkin_version column, schema 7, sits between hic_d and the risks).
std::span<const SummaryField> SummaryFields();

// The field named `name`, or nullptr.
const SummaryField* FindSummaryField(std::string_view name);

// The fields with a risk curve (group kRisk), in table order.
std::vector<const SummaryField*> RiskFields();

// The label of a sentence: the field's label; a risk's names its AIS level
// and criterion, "P(AIS 3+ | HIC15)".
std::string FieldLabel(const SummaryField& field);

// The label of a table row: the label with its detail and unit, "HIC (no
// window limit)", "peak acceleration (g)"; a risk's names its criterion and
// its curve's source, "P(AIS 3+) from HIC15 (NCAP)".
std::string FieldTableLabel(const SummaryField& field);

// The fields of `groups` in contract order: group by group, each in the order
// above. The order of the views' columns, of `napkin query` and of the
// summary JSON (hic_d, added later, follows the other HIC fields; the risks,
// added by schema 8, are their own group).
std::vector<const SummaryField*> SummaryFieldsOf(std::initializer_list<SummaryGroup> groups);

// The names of the fields of `group`, in contract order.
std::vector<std::string> SummaryFieldNames(SummaryGroup group);

// The fields in which two summaries differ: names from SummaryFields(), then
// "findings" when their counts differ, else "findings[i].check", ".channel",
// ".severity", ".detail". Empty when they are the same. Numbers compare by
// value with NaN equal to NaN: the catalogue keeps every double's bits except
// those two distinctions (SQLite stores -0.0 as the integer 0, and a NaN binds
// as NULL and reads back as the quiet NaN), so this is as strict as a
// round trip through the catalogue allows.
std::vector<std::string> DifferingSummaryFields(const TestSummary& a, const TestSummary& b);

}  // namespace napkin::engine
