// Catalogue: merging shard catalogues (PRODUCT.md: `run --shard I/N` on
// several machines, then `merge SHARD.db...`).
//
// The shard is ATTACHed to this connection and copied with INSERT ... SELECT,
// mapping keys through content: tests by content hash, arrays and configs by
// hash, series by name (keys of a shard that imported new tests differ).
#include "db/catalogue.h"
#include "db/catalogue_internal.h"
#include "engine/error.h"

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

// Shard results to take: those whose (test, config) this catalogue lacks or
// holds with an older computation time. Maps shard keys to ours.
constexpr const char* kCreateTakeTable =
    "CREATE TEMP TABLE merge_take AS "
    "SELECT r.id AS shard_result, r.test_id AS shard_test, r.config_id AS shard_config, "
    "mt.id AS test_id, mc.id AS config_id "
    "FROM shard.results AS r "
    "JOIN shard.tests AS st ON st.id = r.test_id JOIN main.tests AS mt ON mt.content_hash = st.content_hash "
    "JOIN shard.configs AS sc ON sc.id = r.config_id JOIN main.configs AS mc ON mc.config_hash = "
    "sc.config_hash "
    "LEFT JOIN main.results AS mr ON mr.test_id = mt.id AND mr.config_id = mc.id "
    "WHERE mr.id IS NULL OR mr.computed_at < r.computed_at";

}  // namespace

MergeReport Catalogue::MergeShard(const std::string& shard_path) {
  {
    // Same checks and one-sentence errors as opening it; read-only also
    // refuses a shard of an older schema version.
    CatalogueOptions options;
    options.read_only = true;
    const Catalogue shard = Catalogue::Open(shard_path, options);
    if (shard.schema_version() != schema_version_)
      throw InputError("shard '" + shard_path + "' has schema version " +
                       std::to_string(shard.schema_version()) + ", the catalogue " +
                       std::to_string(schema_version_) + ".");
  }
  AttachedShard attached(connection_, shard_path);
  MergeReport report;
  Transaction transaction(connection_);

  {
    auto conflict = connection_.Prepare(
        "SELECT st.external_id FROM shard.tests AS st JOIN main.tests AS mt ON mt.external_id = "
        "st.external_id "
        "WHERE mt.content_hash <> st.content_hash ORDER BY st.external_id LIMIT 1");
    if (conflict->Step())
      throw InputError("test '" + conflict->ColumnText(0) + "' in shard '" + shard_path +
                       "' has different content from the catalogue's test of that id.");
  }
  // "WHERE true" keeps SQLite from reading ON CONFLICT as a join constraint.
  connection_
      .Prepare(
          "INSERT INTO main.arrays (name, definition_json, definition_hash) "
          "SELECT name, definition_json, definition_hash FROM shard.arrays WHERE true "
          "ON CONFLICT (definition_hash) DO NOTHING")
      ->Execute();
  connection_
      .Prepare(
          "INSERT INTO main.series (name, description) SELECT name, description FROM shard.series WHERE true "
          "ON CONFLICT (name) DO NOTHING")
      ->Execute();
  connection_
      .Prepare(
          "INSERT INTO main.configs (name, config_json, config_hash, created_at) "
          "SELECT name, config_json, config_hash, created_at FROM shard.configs WHERE true "
          "ON CONFLICT (config_hash) DO NOTHING")
      ->Execute();
  {
    auto tests = connection_.Prepare(
        "INSERT INTO main.tests (external_id, series_id, variant, metadata_json, array_id, "
        "orientation_phi_rad, orientation_theta_rad, orientation_psi_rad, velocity_x_mps, velocity_y_mps, "
        "velocity_z_mps, omega_x_radps, omega_y_radps, omega_z_radps, source_path, content_hash, "
        "imported_at) "
        "SELECT st.external_id, ms.id, st.variant, st.metadata_json, ma.id, "
        "st.orientation_phi_rad, st.orientation_theta_rad, st.orientation_psi_rad, st.velocity_x_mps, "
        "st.velocity_y_mps, st.velocity_z_mps, st.omega_x_radps, st.omega_y_radps, st.omega_z_radps, "
        "st.source_path, st.content_hash, st.imported_at "
        "FROM shard.tests AS st "
        "JOIN shard.arrays AS sa ON sa.id = st.array_id JOIN main.arrays AS ma ON ma.definition_hash = "
        "sa.definition_hash "
        "LEFT JOIN shard.series AS ss ON ss.id = st.series_id LEFT JOIN main.series AS ms ON ms.name = "
        "ss.name "
        "WHERE st.content_hash NOT IN (SELECT content_hash FROM main.tests) ORDER BY st.id");
    tests->Execute();
    report.tests_added = connection_.Changes();
  }
  connection_
      .Prepare(
          "INSERT INTO main.raw_channels (test_id, position, slot, unit, dt_s, t0_s, sample_count, samples) "
          "SELECT mt.id, rc.position, rc.slot, rc.unit, rc.dt_s, rc.t0_s, rc.sample_count, rc.samples "
          "FROM shard.raw_channels AS rc JOIN shard.tests AS st ON st.id = rc.test_id "
          "JOIN main.tests AS mt ON mt.content_hash = st.content_hash "
          "WHERE NOT EXISTS (SELECT 1 FROM main.raw_channels AS x WHERE x.test_id = mt.id)")
      ->Execute();

  {
    // A result of the same test and config with other values is a conflict
    // (a deterministic computation on the same input and config cannot
    // disagree with itself): refuse rather than let the newer one win.
    const std::string shard_values = "(r.solver, " + internal::SummaryColumnList("r.") + ")";
    const std::string main_values = "(mr.solver, " + internal::SummaryColumnList("mr.") + ")";
    auto conflict = connection_.Prepare(
        "SELECT st.external_id, mc.name FROM shard.results AS r "
        "JOIN shard.tests AS st ON st.id = r.test_id JOIN main.tests AS mt ON mt.content_hash = st.content_hash "
        "JOIN shard.configs AS sc ON sc.id = r.config_id JOIN main.configs AS mc ON mc.config_hash = "
        "sc.config_hash "
        "JOIN main.results AS mr ON mr.test_id = mt.id AND mr.config_id = mc.id WHERE " +
        shard_values + " IS NOT " + main_values + " ORDER BY st.external_id LIMIT 1");
    if (conflict->Step())
      throw InputError("test '" + conflict->ColumnText(0) + "' has a result for config '" + conflict->ColumnText(1) +
                       "' in shard '" + shard_path + "' that differs from the catalogue's result.");
  }
  connection_.Execute("DROP TABLE IF EXISTS temp.merge_take");
  connection_.Execute(kCreateTakeTable);
  for (const char* table : {"results", "findings", "derived_channels"})
    connection_.Execute(std::string("DELETE FROM main.") + table +
                        " WHERE (test_id, config_id) IN (SELECT test_id, config_id FROM temp.merge_take)");
  {
    // In the shard's order, so the most recent shard result stays the latest here.
    const std::string columns = internal::SummaryColumnList();
    connection_.Execute(
        "INSERT INTO main.results (test_id, config_id, solver, computed_at, " + columns +
        ") SELECT m.test_id, m.config_id, r.solver, r.computed_at, " + internal::SummaryColumnList("r.") +
        " FROM temp.merge_take AS m JOIN shard.results AS r ON r.id = m.shard_result ORDER BY r.id");
    report.results_merged = connection_.Changes();
  }
  connection_.Execute(
      "INSERT INTO main.findings (test_id, config_id, position, check_name, channel, severity, detail) "
      "SELECT m.test_id, m.config_id, f.position, f.check_name, f.channel, f.severity, f.detail "
      "FROM temp.merge_take AS m JOIN shard.findings AS f "
      "ON f.test_id = m.shard_test AND f.config_id = m.shard_config");
  connection_.Execute(
      "INSERT INTO main.derived_channels (test_id, config_id, name, dt_s, t0_s, sample_count, samples) "
      "SELECT m.test_id, m.config_id, d.name, d.dt_s, d.t0_s, d.sample_count, d.samples "
      "FROM temp.merge_take AS m JOIN shard.derived_channels AS d "
      "ON d.test_id = m.shard_test AND d.config_id = m.shard_config");
  {
    auto done = connection_.Prepare(
        "INSERT INTO main.jobs (test_id, config_id, state, attempts, lease_owner, enqueued_at, started_at, "
        "finished_at, duration_s) "
        "SELECT m.test_id, m.config_id, 'done', coalesce(j.attempts, 0), j.lease_owner, "
        "coalesce(j.enqueued_at, ?1), "
        "j.started_at, j.finished_at, j.duration_s FROM temp.merge_take AS m LEFT JOIN shard.jobs AS j "
        "ON j.test_id = m.shard_test AND j.config_id = m.shard_config WHERE true "
        "ON CONFLICT (test_id, config_id) DO UPDATE SET state = 'done', attempts = excluded.attempts, "
        "lease_owner = excluded.lease_owner, lease_expires_at = NULL, last_error = NULL, "
        "started_at = excluded.started_at, finished_at = excluded.finished_at, duration_s = "
        "excluded.duration_s");
    done->Bind(1, clock_());
    done->Execute();
  }
  {
    // Failures of tests still without a result here (a result wins).
    auto failed = connection_.Prepare(
        "INSERT INTO main.jobs (test_id, config_id, state, attempts, last_error, enqueued_at, started_at, "
        "finished_at, duration_s) "
        "SELECT mt.id, mc.id, 'failed', j.attempts, j.last_error, j.enqueued_at, j.started_at, "
        "j.finished_at, "
        "j.duration_s FROM shard.jobs AS j "
        "JOIN shard.tests AS st ON st.id = j.test_id JOIN main.tests AS mt ON mt.content_hash = "
        "st.content_hash "
        "JOIN shard.configs AS sc ON sc.id = j.config_id JOIN main.configs AS mc ON mc.config_hash = "
        "sc.config_hash "
        "WHERE j.state = 'failed' AND NOT EXISTS "
        "(SELECT 1 FROM main.results AS r WHERE r.test_id = mt.id AND r.config_id = mc.id) "
        "ON CONFLICT (test_id, config_id) DO UPDATE SET state = 'failed', attempts = excluded.attempts, "
        "last_error = excluded.last_error, lease_owner = NULL, lease_expires_at = NULL, "
        "started_at = excluded.started_at, finished_at = excluded.finished_at, duration_s = "
        "excluded.duration_s "
        "WHERE jobs.state <> 'failed' OR jobs.last_error IS NOT excluded.last_error");
    failed->Execute();
    report.failures_merged = connection_.Changes();
  }
  connection_.Execute("DROP TABLE temp.merge_take");
  transaction.Commit();
  return report;
}

}  // namespace napkin::db
