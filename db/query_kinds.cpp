// The table of query kinds (db/query_kinds.h): one row per kind, everything
// the front ends and the catalogue's SELECT need to know of it.
#include "db/query_kinds.h"

#include <algorithm>
#include <stdexcept>

#include "common/error.h"
#include "common/joined.h"
#include "util/text.h"

namespace napkin::db {
namespace {

using engine::SummaryGroup;

std::vector<QueryField> TextFields(std::initializer_list<const char*> names) {
  std::vector<QueryField> fields;
  for (const char* name : names) fields.push_back({name, false});
  return fields;
}

std::vector<QueryField> NumericFields(std::initializer_list<const char*> names) {
  std::vector<QueryField> fields;
  for (const char* name : names) fields.push_back({name, true});
  return fields;
}

std::vector<QueryField> Concatenated(std::initializer_list<std::vector<QueryField>> parts) {
  std::vector<QueryField> fields;
  for (const std::vector<QueryField>& part : parts) fields.insert(fields.end(), part.begin(), part.end());
  return fields;
}

// The table. Columns: docs/formats.md "Query filters" (the fields of each kind)
// and "Per-test summary fields"; views: schema/002_query_views.sql and later.
std::vector<QueryKindSpec> MakeQueryKinds() {
  std::vector<QueryKindSpec> kinds;
  kinds.push_back(
      {.kind = QueryKind::kTests,
       .name = "tests",
       .description = "the tests: source file, array, test information",
       .rows_of = QueryKind::kTests,
       .test_summary = TestSummaryPart::kRow,
       .own_fields = TextFields({"array", "source_path", "content_hash", "imported_at", "position",
                                 "test_number", "title", "vehicle", "dummy", "test_date", "laboratory"}),
       .salvaged = true,
       .latest_source = "v_tests",
       // The tests with a result of that config.
       .config_source = "(SELECT * FROM v_tests WHERE test_id IN (SELECT t.external_id FROM results "
                        "AS r JOIN tests AS t ON t.id = r.test_id WHERE r.config_id = ?CONFIG))"});
  kinds.push_back({.kind = QueryKind::kHic,
                   .name = "hic",
                   .description = "HIC15, HIC36, HIC with their windows, HIC(d), peak and 3 ms acceleration",
                   .rows_of = QueryKind::kHic,
                   .test_summary = TestSummaryPart::kRow,
                   .summary_groups = {SummaryGroup::kHic}});
  kinds.push_back(
      {.kind = QueryKind::kRotation,
       .name = "rotation",
       .description =
           "peak angular velocity and acceleration, BrIC, DAMAGE, UBrIC, final orientation and position",
       .rows_of = QueryKind::kRotation,
       .test_summary = TestSummaryPart::kRow,
       .summary_groups = {SummaryGroup::kRotation}});
  kinds.push_back({.kind = QueryKind::kCriteria,
                   .name = "criteria",
                   .description = "the fields of hic and rotation together",
                   .rows_of = QueryKind::kCriteria,
                   .test_summary = TestSummaryPart::kRow,
                   .summary_groups = {SummaryGroup::kHic, SummaryGroup::kRotation},
                   .salvaged = true});
  kinds.push_back({.kind = QueryKind::kRisk,
                   .name = "risk",
                   .description = "injury risks, P(AIS n+) from HIC and BrIC",
                   .rows_of = QueryKind::kRisk,
                   .test_summary = TestSummaryPart::kRow,
                   .summary_groups = {SummaryGroup::kRisk}});
  kinds.push_back(
      {.kind = QueryKind::kQuality,
       .name = "quality",
       .description = "the screening findings, one row each",
       .rows_of = QueryKind::kQuality,
       .test_summary = TestSummaryPart::kAllRows,
       .own_fields = TextFields({"check", "channel", "severity", "detail"}),
       .latest_source = "v_quality",
       .config_source =
           "(SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,"
           " f.check_name AS \"check\", f.channel AS channel, f.severity AS severity, f.detail AS "
           "detail FROM findings AS f JOIN tests AS t ON t.id = f.test_id"
           " LEFT JOIN series AS s ON s.id = t.series_id WHERE f.config_id = ?CONFIG)",
       .tie_order = ", \"check\", channel, detail"});
  kinds.push_back({.kind = QueryKind::kConditioning,
                   .name = "conditioning",
                   .description = "what conditioning did to each channel: filter, bias removal, time shift",
                   .rows_of = QueryKind::kConditioning,
                   .own_fields = Concatenated({TextFields({"channel", "unit", "filter"}),
                                               NumericFields({"filter_cfc", "prefiltered_cfc", "bias_removed",
                                                              "bias_t1_s", "bias_t2_s", "time_shift_s"})}),
                   .latest_source = "v_conditioning",
                   .config_source =
                       "(SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant, c.channel,"
                       " rc.unit AS unit, c.filter, c.filter_cfc, c.prefiltered_cfc, c.bias_removed, "
                       "c.bias_t1_s, c.bias_t2_s, c.time_shift_s, c.position FROM result_conditioning AS c"
                       " JOIN tests AS t ON t.id = c.test_id LEFT JOIN series AS s ON s.id = t.series_id"
                       " LEFT JOIN raw_channels AS rc ON rc.test_id = c.test_id AND rc.slot = c.channel"
                       " WHERE c.config_id = ?CONFIG)",
                   .tie_order = ", position"});
  kinds.push_back(
      {.kind = QueryKind::kCorrelation,
       .name = "correlation",
       .description = "the stored ISO/TS 18571 ratings of channels against reference curves",
       .rows_of = QueryKind::kCorrelation,
       .own_fields = Concatenated(
           {TextFields({"channel", "reference_kind", "reference", "model_file", "model_sha256",
                        "model_column", "model_units", "reference_test", "edition"}),
            NumericFields({"start_s", "end_s", "corridor", "phase", "magnitude", "slope", "overall"}),
            TextFields({"grade"}), NumericFields({"shift_s"}), TextFields({"config", "rated_at"})}),
       .latest_source = "v_correlation",
       .config_source = "(SELECT * FROM v_correlation WHERE config_id = ?CONFIG)",  // that config's ratings
       .tie_order = ", channel, reference, edition, start_s, end_s, config"});
  kinds.push_back({.kind = QueryKind::kLimits,
                   .name = "limits",
                   .description = "the rows of criteria checked against a limit set (--limits)",
                   .rows_of = QueryKind::kCriteria,
                   .takes_limits = true});
  return kinds;
}

}  // namespace

const std::vector<QueryKindSpec>& QueryKinds() {
  static const std::vector<QueryKindSpec> kinds = MakeQueryKinds();
  return kinds;
}

const QueryKindSpec& QueryKindOf(QueryKind kind) {
  for (const QueryKindSpec& spec : QueryKinds())
    if (spec.kind == kind) return spec;
  throw std::logic_error("query kind " + std::to_string(static_cast<int>(kind)) +
                         " has no row in QueryKinds()");
}

const QueryKindSpec* FindQueryKind(std::string_view name) {
  const std::vector<QueryKindSpec>& kinds = QueryKinds();
  const auto found =
      std::find_if(kinds.begin(), kinds.end(), [&](const QueryKindSpec& spec) { return spec.name == name; });
  return found == kinds.end() ? nullptr : &*found;
}

std::vector<std::string> QueryKindNames() {
  std::vector<std::string> names;
  for (const QueryKindSpec& spec : QueryKinds()) names.push_back(spec.name);
  return names;
}

std::string UnknownQueryKindSentence(std::string_view name) {
  return "the query kind must be " + JoinedChoices(QueryKinds(), &QueryKindSpec::name) + "; it is '" +
         util::Abbreviated(name) + "'.";
}

const QueryKindSpec& ParseQueryKind(std::string_view name) {
  const QueryKindSpec* spec = FindQueryKind(name);
  if (!spec) throw UsageError(UnknownQueryKindSentence(name));
  return *spec;
}

}  // namespace napkin::db
