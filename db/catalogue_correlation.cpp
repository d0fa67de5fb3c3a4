// Catalogue: ISO/TS 18571 ratings (schema/009_correlation.sql; docs/formats.md
// "Correlation ratings"). A rating refers to the results row it rated, so a
// result computed again drops its ratings (ON DELETE CASCADE).
#include "common/error.h"
#include "db/catalogue.h"
#include "db/catalogue_internal.h"

namespace napkin::db {

void Catalogue::WriteCorrelation(const CorrelationRow& record) {
  Transaction transaction(connection_);
  std::int64_t result_id = 0;
  {
    auto result = connection_.Prepare("SELECT id FROM results WHERE test_id = ?1 AND config_id = ?2");
    result->BindAll(record.test, record.config);
    if (!result->Step())
      throw InputError("the rated test has no result under the rated config; run `napkin run` first.");
    result_id = result->ColumnInt64(0);
  }
  {
    auto remove = connection_.Prepare(
        "DELETE FROM correlations WHERE result_id = ?1 AND channel = ?2 AND reference_key = ?3 AND "
        "edition = ?4 AND start_s = ?5 AND end_s = ?6");
    remove->BindAll(result_id, record.channel, record.reference_key, record.edition, record.start_s,
                    record.end_s);
    remove->Execute();
  }
  auto insert = connection_.Prepare(
      "INSERT INTO correlations (result_id, test_id, config_id, channel, reference_kind, reference, "
      "reference_key, model_file, model_sha256, model_column, reference_test_id, reference_series, "
      "reference_variant, edition, start_s, end_s, corridor, phase, magnitude, slope, overall, grade, "
      "shift_s, napkin_version, rated_at, model_units) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, "
      "?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19, ?20, ?21, ?22, ?23, ?24, " +
      internal::IsoTimestampSql("?25") + ", ?26)");
  insert->BindAll(result_id, record.test, record.config, record.channel, record.reference_kind,
                  record.reference, record.reference_key, record.model_file, record.model_sha256,
                  record.model_column, record.reference_test, record.reference_series,
                  record.reference_variant, record.edition, record.start_s, record.end_s, record.corridor,
                  record.phase, record.magnitude, record.slope, record.overall, record.grade, record.shift_s,
                  napkin_version_, clock_(), record.model_units);
  insert->Execute();
  transaction.Commit();
}

std::vector<CorrelationRow> Catalogue::ReadCorrelations(TestId test, ConfigId config) {
  auto select = connection_.Prepare(
      "SELECT channel, reference_kind, reference, reference_key, model_file, model_sha256, model_column, "
      "reference_test_id, reference_series, reference_variant, edition, start_s, end_s, corridor, phase, "
      "magnitude, slope, overall, grade, shift_s, model_units FROM correlations WHERE test_id = ?1 AND "
      "config_id = ?2 "
      "ORDER BY channel, reference, edition, start_s, end_s");
  select->BindAll(test, config);
  std::vector<CorrelationRow> records;
  while (select->Step()) {
    CorrelationRow& record = records.emplace_back();
    record.test = test;
    record.config = config;
    record.channel = select->ColumnText(0);
    record.reference_kind = select->ColumnText(1);
    record.reference = select->ColumnText(2);
    record.reference_key = select->ColumnText(3);
    record.model_file = select->ColumnOptionalText(4);
    record.model_sha256 = select->ColumnOptionalText(5);
    record.model_column = select->ColumnOptionalText(6);
    if (!select->ColumnIsNull(7)) record.reference_test = TestId{select->ColumnInt64(7)};
    record.reference_series = select->ColumnOptionalText(8);
    record.reference_variant = select->ColumnOptionalText(9);
    record.edition = select->ColumnText(10);
    record.start_s = select->ColumnDouble(11);
    record.end_s = select->ColumnDouble(12);
    record.corridor = select->ColumnDouble(13);
    record.phase = select->ColumnDouble(14);
    record.magnitude = select->ColumnDouble(15);
    record.slope = select->ColumnDouble(16);
    record.overall = select->ColumnDouble(17);
    record.grade = select->ColumnText(18);
    record.shift_s = select->ColumnDouble(19);
    record.model_units = select->ColumnOptionalText(20);
  }
  return records;
}

}  // namespace napkin::db
