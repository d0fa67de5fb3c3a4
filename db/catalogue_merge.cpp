// Catalogue: merging shard catalogues (README "Batch runs": `run --shard I/N` on
// several machines, then `merge SHARD.db...`).
//
// The shard is ATTACHed to this connection and copied with INSERT ... SELECT,
// mapping keys through content: tests by content hash, arrays and configs by
// hash, series by name (keys of a shard that imported new tests differ).
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "common/error.h"
#include "db/catalogue.h"
#include "db/catalogue_internal.h"

namespace napkin::db {

namespace {

// ATTACHes a file as schema "shard" for the life of the object.
class AttachedShard {
 public:
  AttachedShard(Connection& connection, const std::string& path) : connection_(connection) {
    auto attach = connection_.Prepare("ATTACH DATABASE ?1 AS shard");
    attach->Bind(1, path);
    attach->Execute();
  }
  ~AttachedShard() { sqlite3_exec(connection_.handle(), "DETACH DATABASE shard", nullptr, nullptr, nullptr); }
  AttachedShard(const AttachedShard&) = delete;
  AttachedShard& operator=(const AttachedShard&) = delete;

 private:
  Connection& connection_;
};

// The shard's rows are mapped to this catalogue's keys through content:
// tests by content hash, arrays and configs by hash, series by name. Each map
// is a temp table merge_<table>_key (shard_id -> main_id), built once, right
// after that table's own rows have been merged.
void MapKeys(Connection& connection, const std::string& table, const std::string& content_column) {
  const std::string map = "merge_" + table + "_key";
  connection.Execute("DROP TABLE IF EXISTS temp." + map);
  connection.Execute("CREATE TEMP TABLE " + map +
                     " (shard_id INTEGER PRIMARY KEY, main_id INTEGER NOT NULL)");
  connection.Execute("INSERT INTO temp." + map + " (shard_id, main_id) SELECT s.id, m.id FROM shard." +
                     table + " AS s JOIN main." + table + " AS m ON m." + content_column + " = s." +
                     content_column);
}

void DropKeyMaps(Connection& connection) {
  for (const char* table : {"arrays", "series", "configs", "tests"})
    connection.Execute(std::string("DROP TABLE IF EXISTS temp.merge_") + table + "_key");
}

// The first text `sql` selects (the test that stops the merge), if any.
std::optional<std::string> FirstText(Connection& connection, std::string_view sql) {
  auto select = connection.Prepare(sql);
  if (!select->Step()) return std::nullopt;
  return select->ColumnText(0);
}

// A test id present on both sides must have the same content on both.
void RefuseConflictingTests(Connection& connection, const std::string& shard_path) {
  const std::optional<std::string> conflict =
      FirstText(connection,
                "SELECT st.external_id FROM shard.tests AS st JOIN main.tests AS mt ON mt.external_id = "
                "st.external_id "
                "WHERE mt.content_hash <> st.content_hash ORDER BY st.external_id LIMIT 1");
  if (conflict)
    throw InputError("test '" + *conflict + "' in shard '" + shard_path +
                     "' has different content from the catalogue's test of that id.");
}

// Arrays, series and configs this catalogue lacks, then their key maps.
void MergeDefinitions(Connection& connection) {
  // "WHERE true" keeps SQLite from reading ON CONFLICT as a join constraint.
  connection
      .Prepare(
          "INSERT INTO main.arrays (name, definition_json, definition_hash) "
          "SELECT name, definition_json, definition_hash FROM shard.arrays WHERE true "
          "ON CONFLICT (definition_hash) DO NOTHING")
      ->Execute();
  connection
      .Prepare(
          "INSERT INTO main.series (name, description) SELECT name, description FROM shard.series WHERE true "
          "ON CONFLICT (name) DO NOTHING")
      ->Execute();
  connection
      .Prepare(
          "INSERT INTO main.configs (name, config_json, config_hash, created_at) "
          "SELECT name, config_json, config_hash, created_at FROM shard.configs WHERE true "
          "ON CONFLICT (config_hash) DO NOTHING")
      ->Execute();
  MapKeys(connection, "arrays", "definition_hash");
  MapKeys(connection, "series", "name");
  MapKeys(connection, "configs", "config_hash");
}

// A shard test this catalogue lacks must come with its raw channels: a
// results file (`run --results`, db/results_file.h) holds test rows without
// them, so it can only bring results of tests already here.
void RefuseTestsWithoutChannels(Connection& connection, const std::string& shard_path,
                                const std::string& catalogue_path) {
  const std::optional<std::string> missing = FirstText(
      connection,
      "SELECT st.external_id FROM shard.tests AS st WHERE st.content_hash NOT IN (SELECT content_hash FROM "
      "main.tests) AND NOT EXISTS (SELECT 1 FROM shard.raw_channels AS rc WHERE rc.test_id = st.id) "
      "ORDER BY st.external_id LIMIT 1");
  if (missing)
    throw InputError("test '" + *missing + "' of '" + shard_path + "' is not in the catalogue '" +
                     catalogue_path +
                     "', and a results file carries no raw channels, so it cannot add tests: merge it into "
                     "the catalogue it was computed from.");
}

// Tests this catalogue lacks, with their raw channels, then the tests' key
// map. Returns the number of tests added.
std::int64_t MergeTests(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.tests (external_id, series_id, variant, metadata_json, array_id, "
      "orientation_phi_rad, orientation_theta_rad, orientation_psi_rad, velocity_x_mps, velocity_y_mps, "
      "velocity_z_mps, omega_x_radps, omega_y_radps, omega_z_radps, source_path, content_hash, "
      "imported_at) "
      "SELECT st.external_id, sk.main_id, st.variant, st.metadata_json, ak.main_id, "
      "st.orientation_phi_rad, st.orientation_theta_rad, st.orientation_psi_rad, st.velocity_x_mps, "
      "st.velocity_y_mps, st.velocity_z_mps, st.omega_x_radps, st.omega_y_radps, st.omega_z_radps, "
      "st.source_path, st.content_hash, st.imported_at "
      "FROM shard.tests AS st JOIN temp.merge_arrays_key AS ak ON ak.shard_id = st.array_id "
      "LEFT JOIN temp.merge_series_key AS sk ON sk.shard_id = st.series_id "
      "WHERE st.content_hash NOT IN (SELECT content_hash FROM main.tests) ORDER BY st.id");
  const std::int64_t added = connection.Changes();
  MapKeys(connection, "tests", "content_hash");
  connection.Execute(
      "INSERT INTO main.raw_channels (test_id, position, slot, unit, dt_s, t0_s, sample_count, samples, "
      "prefiltered_cfc) SELECT tk.main_id, rc.position, rc.slot, rc.unit, rc.dt_s, rc.t0_s, rc.sample_count, "
      "rc.samples, rc.prefiltered_cfc "
      "FROM shard.raw_channels AS rc JOIN temp.merge_tests_key AS tk ON tk.shard_id = rc.test_id "
      "WHERE NOT EXISTS (SELECT 1 FROM main.raw_channels AS x WHERE x.test_id = tk.main_id) ORDER BY rc.id");
  return added;
}

// A result of the same test and config with other values is a conflict (a
// deterministic computation on the same input and config cannot disagree
// with itself): refuse rather than let the newer one win. The napkin version
// is provenance, not a value: equal values computed by two versions agree.
void RefuseConflictingResults(Connection& connection, const std::string& shard_path) {
  const std::string shard_values = "(r.solver, " + internal::SummaryColumnList("r.") + ")";
  const std::string main_values = "(mr.solver, " + internal::SummaryColumnList("mr.") + ")";
  auto conflict = connection.Prepare(
      "SELECT st.external_id, mc.name FROM shard.results AS r JOIN shard.tests AS st ON st.id = r.test_id "
      "JOIN temp.merge_tests_key AS tk ON tk.shard_id = r.test_id "
      "JOIN temp.merge_configs_key AS ck ON ck.shard_id = r.config_id JOIN main.configs AS mc ON mc.id = "
      "ck.main_id "
      "JOIN main.results AS mr ON mr.test_id = tk.main_id AND mr.config_id = ck.main_id WHERE " +
      shard_values + " IS NOT " + main_values + " ORDER BY st.external_id LIMIT 1");
  if (conflict->Step())
    throw InputError("test '" + conflict->ColumnText(0) + "' has a result for config '" +
                     conflict->ColumnText(1) + "' in shard '" + shard_path +
                     "' that differs from the catalogue's result.");
}

// temp.merge_take: the shard results to take, those whose (test, config) this
// catalogue lacks or holds with an older computation time, in the shard's
// order, with their keys on both sides.
void SelectResultsToTake(Connection& connection) {
  connection.Execute("DROP TABLE IF EXISTS temp.merge_take");
  connection.Execute(
      "CREATE TEMP TABLE merge_take AS "
      "SELECT r.id AS shard_result, r.test_id AS shard_test, r.config_id AS shard_config, "
      "tk.main_id AS test_id, ck.main_id AS config_id "
      "FROM shard.results AS r JOIN temp.merge_tests_key AS tk ON tk.shard_id = r.test_id "
      "JOIN temp.merge_configs_key AS ck ON ck.shard_id = r.config_id "
      "LEFT JOIN main.results AS mr ON mr.test_id = tk.main_id AND mr.config_id = ck.main_id "
      "WHERE mr.id IS NULL OR mr.computed_at < r.computed_at ORDER BY r.id");
}

// The columns of a rating but its key and its result's key (schema/009_correlation.sql, 010).
constexpr const char* kRatingColumns =
    "test_id, config_id, channel, reference_kind, reference, reference_key, model_file, model_sha256, "
    "model_column, model_units, reference_test_id, reference_series, reference_variant, edition, start_s, "
    "end_s, corridor, phase, magnitude, slope, overall, grade, shift_s, rated_at, napkin_version";

// A rating this catalogue cannot carry: one against a test it does not hold (a results file with the
// rating but not the test it was rated against). Refused whole, before anything is written.
void RefuseRatingsAgainstMissingTests(Connection& connection, const std::string& shard_path,
                                      const std::string& catalogue_path) {
  auto missing = connection.Prepare(
      "SELECT st.external_id, c.channel, rt.external_id FROM shard.correlations AS c "
      "JOIN shard.tests AS st ON st.id = c.test_id JOIN shard.tests AS rt ON rt.id = c.reference_test_id "
      "WHERE c.reference_test_id IS NOT NULL AND NOT EXISTS "
      "(SELECT 1 FROM temp.merge_tests_key AS k WHERE k.shard_id = c.reference_test_id) "
      "ORDER BY st.external_id LIMIT 1");
  if (missing->Step())
    throw InputError("the rating of test '" + missing->ColumnText(0) + "' channel " + missing->ColumnText(1) +
                     " against test '" + missing->ColumnText(2) + "' in '" + shard_path +
                     "' cannot be merged: test '" + missing->ColumnText(2) + "' is not in the catalogue '" +
                     catalogue_path + "'; merge the catalogue that holds it first.");
}

// This catalogue's ratings of the results about to be replaced by the shard's (equal values,
// RefuseConflictingResults): kept aside in temp.merge_kept_ratings, so that replacing a result does
// not drop the ratings that still describe it.
void KeepRatingsOfReplacedResults(Connection& connection) {
  connection.Execute("DROP TABLE IF EXISTS temp.merge_kept_ratings");
  connection.Execute(std::string("CREATE TEMP TABLE merge_kept_ratings AS SELECT ") + kRatingColumns +
                     " FROM main.correlations WHERE (test_id, config_id) IN "
                     "(SELECT test_id, config_id FROM temp.merge_take) ORDER BY id");
}

// The kept ratings onto the results that replaced theirs, then the shard's ratings, mapped to this
// catalogue's keys, onto this catalogue's result of their (test, config), which after the merge
// exists and has the shard's values. One rating per identity (result, channel, reference key with
// its model units, edition, interval): the more recently rated wins. Returns the shard's ratings
// new here or newer than the catalogue's.
std::int64_t MergeRatings(Connection& connection) {
  const std::string insert =
      std::string("INSERT INTO main.correlations (result_id, ") + kRatingColumns + ") ";
  connection.Execute(insert +
                     "SELECT r.id, k.test_id, k.config_id, k.channel, k.reference_kind, k.reference, "
                     "k.reference_key, k.model_file, k.model_sha256, k.model_column, k.model_units, "
                     "k.reference_test_id, k.reference_series, k.reference_variant, k.edition, k.start_s, "
                     "k.end_s, k.corridor, k.phase, k.magnitude, k.slope, k.overall, k.grade, k.shift_s, "
                     "k.rated_at, k.napkin_version FROM temp.merge_kept_ratings AS k "
                     "JOIN main.results AS r ON r.test_id = k.test_id AND r.config_id = k.config_id "
                     "WHERE true ON CONFLICT (result_id, channel, reference_key, edition, start_s, end_s) "
                     "DO NOTHING");
  connection.Execute("DROP TABLE temp.merge_kept_ratings");
  connection.Execute(
      insert +
      "SELECT r.id, tk.main_id, ck.main_id, c.channel, c.reference_kind, c.reference, "
      "c.reference_key, c.model_file, c.model_sha256, c.model_column, c.model_units, "
      "rk.main_id, c.reference_series, c.reference_variant, c.edition, c.start_s, c.end_s, "
      "c.corridor, c.phase, c.magnitude, c.slope, c.overall, c.grade, c.shift_s, c.rated_at, "
      "c.napkin_version FROM shard.correlations AS c "
      "JOIN temp.merge_tests_key AS tk ON tk.shard_id = c.test_id "
      "JOIN temp.merge_configs_key AS ck ON ck.shard_id = c.config_id "
      "JOIN main.results AS r ON r.test_id = tk.main_id AND r.config_id = ck.main_id "
      "LEFT JOIN temp.merge_tests_key AS rk ON rk.shard_id = c.reference_test_id "
      "WHERE true ORDER BY c.id "
      "ON CONFLICT (result_id, channel, reference_key, edition, start_s, end_s) DO UPDATE SET "
      "reference = excluded.reference, model_file = excluded.model_file, "
      "corridor = excluded.corridor, phase = excluded.phase, magnitude = excluded.magnitude, "
      "slope = excluded.slope, overall = excluded.overall, grade = excluded.grade, "
      "shift_s = excluded.shift_s, rated_at = excluded.rated_at, "
      "napkin_version = excluded.napkin_version WHERE excluded.rated_at > correlations.rated_at");
  return connection.Changes();
}

// The taken results replace this catalogue's results, findings, conditioning
// records and derived channels of their (test, config). Returns the number of results merged.
std::int64_t MergeResults(Connection& connection) {
  for (const char* table :
       {"results", "findings", "result_conditioning", "result_salvage", "derived_channels"})
    connection.Execute(std::string("DELETE FROM main.") + table +
                       " WHERE (test_id, config_id) IN (SELECT test_id, config_id FROM temp.merge_take)");
  // In the shard's order, so the most recent shard result stays the latest here.
  const std::string columns = internal::SummaryColumnList();
  // The napkin version that computed each result comes with it (schema/007_provenance.sql).
  connection.Execute("INSERT INTO main.results (test_id, config_id, solver, computed_at, " + columns +
                     ", napkin_version) SELECT m.test_id, m.config_id, r.solver, r.computed_at, " +
                     internal::SummaryColumnList("r.") +
                     ", r.napkin_version FROM temp.merge_take AS m "
                     "JOIN shard.results AS r ON r.id = m.shard_result ORDER BY r.id");
  return connection.Changes();
}

void MergeFindings(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.findings (test_id, config_id, position, check_name, channel, severity, detail) "
      "SELECT m.test_id, m.config_id, f.position, f.check_name, f.channel, f.severity, f.detail "
      "FROM temp.merge_take AS m JOIN shard.findings AS f "
      "ON f.test_id = m.shard_test AND f.config_id = m.shard_config");
}

void MergeConditioning(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.result_conditioning (test_id, config_id, position, channel, filter, filter_cfc, "
      "prefiltered_cfc, bias_removed, bias_t1_s, bias_t2_s, time_shift_s) "
      "SELECT m.test_id, m.config_id, c.position, c.channel, c.filter, c.filter_cfc, c.prefiltered_cfc, "
      "c.bias_removed, c.bias_t1_s, c.bias_t2_s, c.time_shift_s "
      "FROM temp.merge_take AS m JOIN shard.result_conditioning AS c "
      "ON c.test_id = m.shard_test AND c.config_id = m.shard_config");
}

void MergeSalvage(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.result_salvage (test_id, config_id, position, mode, channel, fault, action, partner, "
      "t1_s, t2_s, samples_replaced, rms_residual_before_g, rms_residual_after_g, channels_used, "
      "channels_total, repaired_samples) SELECT m.test_id, m.config_id, v.position, v.mode, v.channel, "
      "v.fault, "
      "v.action, v.partner, v.t1_s, v.t2_s, v.samples_replaced, v.rms_residual_before_g, "
      "v.rms_residual_after_g, v.channels_used, v.channels_total, v.repaired_samples FROM temp.merge_take AS "
      "m JOIN shard.result_salvage AS v "
      "ON v.test_id = m.shard_test AND v.config_id = m.shard_config");
}

void MergeDerivedChannels(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.derived_channels (test_id, config_id, name, dt_s, t0_s, sample_count, encoding, "
      "samples) SELECT m.test_id, m.config_id, d.name, d.dt_s, d.t0_s, d.sample_count, d.encoding, d.samples "
      "FROM temp.merge_take AS m JOIN shard.derived_channels AS d "
      "ON d.test_id = m.shard_test AND d.config_id = m.shard_config");
}

// The findings of the shard's failed jobs of tests still without a result
// here replace this catalogue's findings of that test and config (when they
// differ, so merging a shard twice changes nothing), as the
// scheduler's WriteFindings does for a failure with findings (a screening
// failure, jobs/scheduler.h).
void MergeFailureFindings(Connection& connection) {
  connection.Execute("DROP TABLE IF EXISTS temp.merge_failed");
  connection.Execute(
      "CREATE TEMP TABLE merge_failed AS SELECT j.test_id AS shard_test, j.config_id AS shard_config, "
      "tk.main_id AS test_id, ck.main_id AS config_id FROM shard.jobs AS j "
      "JOIN temp.merge_tests_key AS tk ON tk.shard_id = j.test_id "
      "JOIN temp.merge_configs_key AS ck ON ck.shard_id = j.config_id "
      "WHERE j.state = 'failed' AND NOT EXISTS "
      "(SELECT 1 FROM main.results AS r WHERE r.test_id = tk.main_id AND r.config_id = ck.main_id) "
      "AND EXISTS (SELECT 1 FROM shard.findings AS f WHERE f.test_id = j.test_id AND f.config_id = "
      "j.config_id) AND ("
      "EXISTS (SELECT position, check_name, channel, severity, detail FROM shard.findings "
      "WHERE test_id = j.test_id AND config_id = j.config_id EXCEPT SELECT position, check_name, channel, "
      "severity, detail FROM main.findings WHERE test_id = tk.main_id AND config_id = ck.main_id) OR "
      "EXISTS (SELECT position, check_name, channel, severity, detail FROM main.findings "
      "WHERE test_id = tk.main_id AND config_id = ck.main_id EXCEPT SELECT position, check_name, channel, "
      "severity, detail FROM shard.findings WHERE test_id = j.test_id AND config_id = j.config_id))");
  connection.Execute(
      "DELETE FROM main.findings WHERE (test_id, config_id) IN (SELECT test_id, config_id FROM "
      "temp.merge_failed)");
  connection.Execute(
      "INSERT INTO main.findings (test_id, config_id, position, check_name, channel, severity, detail) "
      "SELECT m.test_id, m.config_id, f.position, f.check_name, f.channel, f.severity, f.detail "
      "FROM temp.merge_failed AS m JOIN shard.findings AS f "
      "ON f.test_id = m.shard_test AND f.config_id = m.shard_config ORDER BY f.id");
  connection.Execute("DROP TABLE temp.merge_failed");
}

// Job state: the taken results' jobs are done; failures of tests still
// without a result here are failed (a result wins). Returns the number of
// failures merged (a failure under another napkin version is merged too).
std::int64_t MergeJobState(Connection& connection, double now) {
  {
    auto done = connection.Prepare(
        "INSERT INTO main.jobs (test_id, config_id, state, attempts, lease_owner, enqueued_at, started_at, "
        "finished_at, duration_s, napkin_version) "
        "SELECT m.test_id, m.config_id, 'done', coalesce(j.attempts, 0), j.lease_owner, "
        "coalesce(j.enqueued_at, ?1), "
        "j.started_at, j.finished_at, j.duration_s, j.napkin_version FROM temp.merge_take AS m "
        "LEFT JOIN shard.jobs AS j ON j.test_id = m.shard_test AND j.config_id = m.shard_config WHERE true "
        "ON CONFLICT (test_id, config_id) DO UPDATE SET state = 'done', attempts = excluded.attempts, "
        "lease_owner = excluded.lease_owner, lease_expires_at = NULL, last_error = NULL, "
        "started_at = excluded.started_at, finished_at = excluded.finished_at, duration_s = "
        "excluded.duration_s, napkin_version = excluded.napkin_version");
    done->Bind(1, now);
    done->Execute();
  }
  connection.Execute(
      "INSERT INTO main.jobs (test_id, config_id, state, attempts, last_error, enqueued_at, started_at, "
      "finished_at, duration_s, napkin_version) "
      "SELECT tk.main_id, ck.main_id, 'failed', j.attempts, j.last_error, j.enqueued_at, j.started_at, "
      "j.finished_at, j.duration_s, j.napkin_version FROM shard.jobs AS j "
      "JOIN temp.merge_tests_key AS tk ON tk.shard_id = j.test_id "
      "JOIN temp.merge_configs_key AS ck ON ck.shard_id = j.config_id "
      "WHERE j.state = 'failed' AND NOT EXISTS "
      "(SELECT 1 FROM main.results AS r WHERE r.test_id = tk.main_id AND r.config_id = ck.main_id) "
      "ORDER BY j.id "
      "ON CONFLICT (test_id, config_id) DO UPDATE SET state = 'failed', attempts = excluded.attempts, "
      "last_error = excluded.last_error, lease_owner = NULL, lease_expires_at = NULL, "
      "started_at = excluded.started_at, finished_at = excluded.finished_at, duration_s = "
      "excluded.duration_s, napkin_version = excluded.napkin_version "
      "WHERE jobs.state <> 'failed' OR jobs.last_error IS NOT excluded.last_error "
      "OR jobs.napkin_version IS NOT excluded.napkin_version");
  return connection.Changes();
}

// The shard's inbox failures (schema/016_inbox_failures.sql) of tests this catalogue has not
// imported since, each newer than this catalogue's failure of the same source: a catalogue a
// service wrote, merged into another, keeps what its inbox could not import.
std::int64_t MergeInboxFailures(Connection& connection) {
  connection.Execute(
      "INSERT INTO main.inbox_failures (source, test_name, series, variant, kind, error, signature, "
      "failed_at) SELECT source, test_name, series, variant, kind, error, signature, failed_at "
      "FROM shard.inbox_failures AS f WHERE NOT EXISTS (SELECT 1 FROM main.tests AS t WHERE "
      "t.source_path = f.source) "
      "ON CONFLICT (source) DO UPDATE SET test_name = excluded.test_name, series = excluded.series, "
      "variant = excluded.variant, kind = excluded.kind, error = excluded.error, "
      "signature = excluded.signature, failed_at = excluded.failed_at "
      "WHERE excluded.failed_at > inbox_failures.failed_at");
  return connection.Changes();
}

// The merge of the shard ATTACHed as "shard", in one transaction.
MergeReport MergeAttachedShard(Connection& connection, const std::string& shard_path,
                               const std::function<double()>& clock) {
  MergeReport report;
  Transaction transaction(connection);
  RefuseConflictingTests(connection, shard_path);
  RefuseTestsWithoutChannels(connection, shard_path, connection.path());
  MergeDefinitions(connection);
  report.tests_added = MergeTests(connection);
  RefuseConflictingResults(connection, shard_path);
  RefuseRatingsAgainstMissingTests(connection, shard_path, connection.path());
  SelectResultsToTake(connection);
  KeepRatingsOfReplacedResults(connection);
  report.results_merged = MergeResults(connection);
  MergeFindings(connection);
  MergeConditioning(connection);
  MergeSalvage(connection);
  MergeDerivedChannels(connection);
  report.ratings_merged = MergeRatings(connection);
  MergeFailureFindings(connection);
  report.failures_merged = MergeJobState(connection, clock());
  report.inbox_failures_merged = MergeInboxFailures(connection);
  connection.Execute("DROP TABLE temp.merge_take");
  DropKeyMaps(connection);
  transaction.Commit();
  return report;
}

// A shard (or results file) whose pages SQLite finds malformed. It names the
// shard, never the catalogue, which is sound and must not be "restored".
InputError DamagedShard(const std::string& shard_path, const std::string& catalogue_path) {
  return InputError("shard '" + shard_path +
                    "' is damaged (SQLite finds a malformed page), so nothing was merged from it into the "
                    "catalogue '" +
                    catalogue_path +
                    "'; compute that shard again (`run --shard I/N --results FILE`) or copy it again from "
                    "where it was computed, and merge the new file.");
}

}  // namespace

MergeReport Catalogue::MergeShard(const std::string& shard_path) {
  try {
    // Same checks and one-sentence errors as opening it; read-only also
    // refuses a shard of an older schema version.
    // The file each name leads to, compared by device and inode, so no
    // spelling of the name (relative, "./", links, a hard link, a "file:"
    // URI) gets the catalogue attached to itself, where the merge would wait
    // on its own lock: before the shard is opened, since SQLite would make a
    // -wal file of the shard's name beside it, and again on the file SQLite
    // opened.
    const InputError itself("shard '" + shard_path + "' is the catalogue '" + connection_.path() +
                            "' itself; merge other catalogues into it.");
    const std::optional<FileIdentity> catalogue_file = connection_.FileIdentityOf();
    if (catalogue_file && IdentifyFile(shard_path) == catalogue_file) throw itself;
    CatalogueOptions options;
    options.read_only = true;
    options.what = "shard";
    Catalogue shard = Catalogue::Open(shard_path, options);
    if (catalogue_file && shard.connection_.FileIdentityOf() == catalogue_file) throw itself;
    if (shard.schema_version() != schema_version_)
      throw InputError("shard '" + shard_path + "' has schema version " +
                       std::to_string(shard.schema_version()) + ", the catalogue " +
                       std::to_string(schema_version_) + ".");
    // A truncated or overwritten shard (a copy cut short) is refused before
    // anything is read from it: its damage is its own, not the catalogue's.
    if (!internal::PassesQuickCheck(shard.connection_)) throw DamagedShard(shard_path, connection_.path());
  } catch (const DatabaseError& error) {
    if (error.corrupt()) throw DamagedShard(shard_path, connection_.path());
    throw;
  }
  AttachedShard attached(connection_, shard_path);
  try {
    return MergeAttachedShard(connection_, shard_path, clock_);
  } catch (const DatabaseError& error) {
    // quick_check does not read the indexes' contents: a malformed page found
    // during the merge is the shard's when its check fails now, else the
    // catalogue's (reported as such by cli/diagnostics.cpp).
    if (error.corrupt() && !internal::PassesQuickCheck(connection_, "shard"))
      throw DamagedShard(shard_path, connection_.path());
    throw;
  }
}

}  // namespace napkin::db
