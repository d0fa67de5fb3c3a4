// JobQueue: the job queue of the batch scheduler.
//
// Design: one row per (test, config) in `jobs`. Workers (threads with their
// own connection, or processes) claim jobs in a BEGIN IMMEDIATE transaction,
// so two claims are serialised by SQLite's write lock and never return the
// same job. A claim is a lease: if the worker dies, the lease expires and the
// job becomes claimable again (attempts counts claims, so a job that keeps
// killing workers is visible). Completing or failing a job checks the caller
// still holds it.
#include "db/job_queue.h"

#include <algorithm>
#include <stdexcept>

#include "common/error.h"
#include "db/catalogue_internal.h"

namespace napkin::db {

namespace internal {

// The tests of a JobScope: the terms of its test filter (catalogue_internal.h,
// ?1..?3) and of its shard, ?4 (count) and ?5 (index); only those it sets, so
// that a scope of a few named tests or one series is read through the
// indexes, not by a walk of every test of the catalogue.
std::string JobScopeCte(const JobScope& scope) {
  std::string cte =
      "scope AS (SELECT t.id AS test_id FROM tests AS t LEFT JOIN series AS s ON s.id = t.series_id WHERE " +
      TestFilterTerms(scope.tests);
  if (scope.shard) cte += " AND t.id % ?4 = ?5";
  return cte + ")";
}

// Whether the test `test_column` (a column holding a test key) is in `scope`,
// as a term to AND to a WHERE clause: looked up by key for each row (never a
// walk of the scope), and nothing at all for the whole catalogue.
std::string InJobScope(const std::string& test_column, const JobScope& scope) {
  std::string terms;
  const TestFilter& filter = scope.tests;
  if (!filter.empty())
    terms +=
        " AND EXISTS (SELECT 1 FROM tests AS t LEFT JOIN series AS s ON s.id = t.series_id WHERE t.id = " +
        test_column + " AND " + TestFilterTerms(filter) + ")";
  if (scope.shard) terms += " AND " + test_column + " % ?4 = ?5";
  return terms;
}

// A result of the test `test_column` under config ?10 that needs no recomputation:
// any result, or with run --outdated (?13 = this napkin version, else NULL) one
// computed by this version.
std::string UpToDateResult(const std::string& test_column) {
  return "SELECT 1 FROM results AS r WHERE r.test_id = " + test_column +
         " AND r.config_id = ?10 AND (?13 IS NULL OR r.napkin_version IS ?13)";
}

void BindJobScope(Statement& statement, const JobScope& scope) {
  internal::BindTestFilter(statement, scope.tests);
  if (scope.shard) {
    if (scope.shard->count < 1 || scope.shard->index < 0 || scope.shard->index >= scope.shard->count)
      throw InputError("shard " + std::to_string(scope.shard->index) + "/" +
                       std::to_string(scope.shard->count) + " is invalid (expected I/N with 0 <= I < N).");
    statement.Bind(4, scope.shard->count);
    statement.Bind(5, scope.shard->index);
  }
}

std::vector<std::string> EnqueueSql(const JobScope& scope) {
  const std::string with = "WITH " + JobScopeCte(scope);
  return {
      // Tests without a job for this config and without a result (a result
      // without a job comes from a merged shard catalogue: it is done).
      with +
          " INSERT INTO jobs (test_id, config_id, state, enqueued_at) "
          "SELECT scope.test_id, ?10, 'queued', ?11 FROM scope "
          "WHERE NOT EXISTS (SELECT 1 FROM jobs AS j WHERE j.test_id = scope.test_id AND j.config_id = ?10) "
          "AND (?12 OR NOT EXISTS (" +
          UpToDateResult("scope.test_id") + "))",
      // Existing jobs: failed ones, done ones whose result is gone, and with
      // `force` every done one. Running jobs are left to their worker (or to
      // lease expiry); earlier results are never deleted here. Each test of
      // the scope looks up its own job (CROSS JOIN: the scope first), rather
      // than every job of the config looking for its test in the scope.
      with +
          " UPDATE jobs SET state = 'queued', enqueued_at = ?11, lease_owner = NULL, lease_expires_at = "
          "NULL, "
          "started_at = NULL, finished_at = NULL, duration_s = NULL "
          "WHERE id IN (SELECT j.id FROM scope CROSS JOIN jobs AS j ON j.test_id = scope.test_id "
          "AND j.config_id = ?10 WHERE j.state = 'failed' OR (j.state = 'done' AND (?12 OR NOT EXISTS (" +
          UpToDateResult("j.test_id") + "))))"};
}

std::string ClaimSql(const JobScope& scope) {
  // Claimable: queued, or running under an expired lease. The queued jobs
  // are walked in key order through the index jobs_by_config_state (config,
  // state, then the key: schema/014_catalogue_scale.sql) from ?15, the last
  // job this queue claimed, so a claim reads the few jobs it takes (and the
  // queued jobs outside its scope only once a pass), never the whole queue;
  // the expired leases are few. The first ?14 of both, in key order.
  const std::string in_scope = InJobScope("j.test_id", scope);
  return "UPDATE jobs SET state = 'running', lease_owner = ?11, lease_expires_at = ?12 + ?13, started_at = "
         "?12, "
         "finished_at = NULL, duration_s = NULL, attempts = attempts + 1 "
         "WHERE id IN (SELECT id FROM (SELECT j.id FROM jobs AS j WHERE j.config_id = ?10 AND j.state = "
         "'queued' "
         "AND j.id > ?15" +
         in_scope +
         " ORDER BY j.id LIMIT ?14) "
         "UNION ALL SELECT id FROM (SELECT j.id FROM jobs AS j WHERE j.config_id = ?10 AND j.state = "
         "'running' "
         "AND j.lease_expires_at <= ?12" +
         in_scope + " ORDER BY j.id LIMIT ?14) ORDER BY 1 LIMIT ?14) RETURNING id, test_id, attempts";
}

}  // namespace internal

namespace {

using internal::BindJobScope;

std::string ScopeCte(const JobScope& scope) { return internal::JobScopeCte(scope); }

// Whether `scope` is every test of the catalogue (no filter, no shard).
bool IsWholeCatalogue(const JobScope& scope) { return !scope.shard && scope.tests.empty(); }

// The parameters of a statement over one config's jobs of a scope: the
// scope (?1..?5) and the config (?10).
void BindConfigScope(Statement& statement, ConfigId config, const JobScope& scope) {
  BindJobScope(statement, scope);
  statement.Bind(10, config);
}

// Runs `sql`, an UPDATE of job ?1 while it is running under lease owner ?2,
// with the parameters `bind` binds, in a transaction of its own; true when
// the job was still held (one row changed).
template <typename Bind>
bool UpdateHeldJob(Connection& connection, std::string_view sql, Bind bind) {
  Transaction transaction(connection);
  auto update = connection.Prepare(sql);
  bind(*update);
  update->Execute();
  const bool held = connection.Changes() == 1;
  transaction.Commit();
  return held;
}

}  // namespace

JobQueue::JobQueue(Catalogue& catalogue)
    : connection_(catalogue.connection_),
      clock_(catalogue.clock_),
      napkin_version_(catalogue.napkin_version_) {}

std::int64_t JobQueue::EnqueueMissing(ConfigId config, const JobScope& scope, bool force, bool outdated) {
  // Both statements bind the scope (?1-?9), the config (?10), the time
  // (?11), `force` (?12) and, for `outdated`, this napkin's version (?13;
  // unbound, NULL: any version is up to date). Returns the jobs (re)queued.
  const auto queue = [&](const std::string& sql) {
    auto statement = connection_.Prepare(sql);
    BindConfigScope(*statement, config, scope);
    statement->Bind(11, clock_());
    statement->Bind(12, force);
    if (outdated) statement->Bind(13, napkin_version_);
    statement->Execute();
    return connection_.Changes();
  };
  Transaction transaction(connection_);
  std::int64_t queued = 0;
  for (const std::string& sql : internal::EnqueueSql(scope)) queued += queue(sql);
  transaction.Commit();
  return queued;
}

std::vector<Job> JobQueue::ClaimJobs(ConfigId config, const std::string& owner, int max_jobs,
                                     double lease_seconds, const JobScope& scope) {
  if (max_jobs <= 0) return {};
  if (!(lease_seconds > 0.0)) throw std::invalid_argument("ClaimJobs: lease_seconds must be positive");
  const double now = clock_();
  // The walk goes on after the last job claimed under this config; a claim
  // that finds fewer than it wants there looks again from the start (jobs
  // put back in the queue: released leases, failures queued again), so the
  // cursor only orders the claims, never changes how many a claim gets.
  if (config != claim_config_) claim_after_ = 0;
  claim_config_ = config;
  Transaction transaction(connection_);  // BEGIN IMMEDIATE: claims are serialised
  const std::string sql = internal::ClaimSql(scope);
  std::vector<Job> jobs;
  // Claims up to what is still wanted among the jobs after key `after`;
  // the cursor moves to the last one claimed.
  const auto claim_after = [&](std::int64_t after) {
    auto claim = connection_.Prepare(sql);
    BindConfigScope(*claim, config, scope);
    claim->Bind(11, owner);
    claim->Bind(12, now);
    claim->Bind(13, lease_seconds);
    claim->Bind(14, max_jobs - static_cast<int>(jobs.size()));
    claim->Bind(15, after);
    std::int64_t last = -1;
    while (claim->Step()) {
      jobs.push_back({JobId{claim->ColumnInt64(0)}, TestId{claim->ColumnInt64(1)}, config,
                      static_cast<int>(claim->ColumnInt64(2))});
      last = std::max(last, claim->ColumnInt64(0));
    }
    if (last >= 0) claim_after_ = last;
  };
  const std::int64_t cursor = claim_after_;
  claim_after(cursor);
  if (cursor > 0 && static_cast<int>(jobs.size()) < max_jobs) claim_after(0);
  transaction.Commit();
  std::sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.id < b.id; });
  return jobs;
}

std::vector<std::string> JobQueue::ReadLeaseOwners(ConfigId config, const JobScope& scope) {
  // The running jobs (a few per worker), each looked up in the scope.
  auto select = connection_.Prepare(
      "SELECT DISTINCT j.lease_owner FROM jobs AS j WHERE j.config_id = ?10 AND j.state = 'running'" +
      internal::InJobScope("j.test_id", scope) + " ORDER BY j.lease_owner");
  BindConfigScope(*select, config, scope);
  std::vector<std::string> owners;
  while (select->Step()) owners.push_back(select->ColumnText(0));
  return owners;
}

std::int64_t JobQueue::ReleaseLeases(ConfigId config, const std::string& owner) {
  Transaction transaction(connection_);
  auto release = connection_.Prepare(
      "UPDATE jobs SET state = 'queued', lease_owner = NULL, lease_expires_at = NULL, started_at = NULL "
      "WHERE config_id = ?1 AND state = 'running' AND lease_owner = ?2");
  release->BindAll(config, owner);
  release->Execute();
  const std::int64_t released = connection_.Changes();
  transaction.Commit();
  return released;
}

bool JobQueue::RenewLease(JobId job, const std::string& owner, double lease_seconds) {
  return UpdateHeldJob(
      connection_,
      "UPDATE jobs SET lease_expires_at = ?3 + ?4 WHERE id = ?1 AND state = 'running' AND lease_owner = ?2",
      [&](Statement& renew) { renew.BindAll(job, owner, clock_(), lease_seconds); });
}

bool JobQueue::CompleteJob(JobId job, const std::string& owner) {
  return UpdateHeldJob(
      connection_,
      "UPDATE jobs SET state = 'done', finished_at = ?3, duration_s = ?3 - started_at, lease_expires_at = "
      "NULL, "
      "last_error = NULL, napkin_version = ?4 WHERE id = ?1 AND state = 'running' AND lease_owner = ?2",
      [&](Statement& complete) { complete.BindAll(job, owner, clock_(), napkin_version_); });
}

bool JobQueue::FailJob(JobId job, const std::string& owner, const std::string& error) {
  return UpdateHeldJob(
      connection_,
      "UPDATE jobs SET state = 'failed', last_error = ?4, finished_at = ?3, duration_s = ?3 - started_at, "
      "lease_expires_at = NULL, napkin_version = ?5 WHERE id = ?1 AND state = 'running' AND lease_owner = "
      "?2",
      [&](Statement& fail) { fail.BindAll(job, owner, clock_(), error, napkin_version_); });
}

StatusCounts JobQueue::ReadStatusCounts(ConfigId config, const JobScope& scope) {
  // One consistent snapshot for the counts and the failure list.
  Transaction transaction(connection_, Transaction::Mode::kDeferred);
  StatusCounts counts;
  // Each statement reads the config's jobs of the scope (?1..?5, ?10), its rows handed to `read`.
  auto scoped = [&](const std::string& sql, const auto& read) {
    auto statement = connection_.Prepare(sql);
    BindConfigScope(*statement, config, scope);
    read(*statement);
  };
  {
    // A test's state: its job's, unless the job is done (or absent), in
    // which case it is done if a result exists and pending otherwise.
    // Over the whole catalogue, the same counts from the indexes alone
    // (docs/architecture.md "Catalogues of a million tests"): the tests, the
    // config's jobs by state and its results, and the results of tests whose
    // job is not done (they count by their job's state); a test's result
    // and job are one row each (UNIQUE (test_id, config_id)).
    const std::string counts_sql =
        IsWholeCatalogue(scope)
            ? "WITH jobs_by_state AS (SELECT "
              "(SELECT count(*) FROM jobs WHERE config_id = ?10 AND state = 'failed') AS failed, "
              "(SELECT count(*) FROM jobs WHERE config_id = ?10 AND state = 'running') AS running), "
              "done AS (SELECT (SELECT count(*) FROM results WHERE config_id = ?10) - "
              "(SELECT count(*) FROM jobs AS j WHERE j.config_id = ?10 AND j.state IN ('queued', 'running', "
              "'failed') "
              "AND EXISTS (SELECT 1 FROM results AS r WHERE r.test_id = j.test_id AND r.config_id = ?10)) AS "
              "done), "
              "all_tests AS (SELECT count(*) AS tests FROM tests) "
              "SELECT tests, done, failed, tests - done - failed - running, running "
              "FROM all_tests, done, jobs_by_state"
            : "WITH " + ScopeCte(scope) +
                  ", states AS (SELECT CASE "
                  "WHEN j.state IN ('queued', 'running', 'failed') THEN j.state "
                  "WHEN EXISTS (SELECT 1 FROM results AS r WHERE r.test_id = scope.test_id AND r.config_id = "
                  "?10) "
                  "THEN 'done' "
                  "ELSE 'queued' END AS state "
                  "FROM scope LEFT JOIN jobs AS j ON j.test_id = scope.test_id AND j.config_id = ?10) "
                  "SELECT count(*), coalesce(sum(state = 'done'), 0), coalesce(sum(state = 'failed'), 0), "
                  "coalesce(sum(state = 'queued'), 0), coalesce(sum(state = 'running'), 0) FROM states";
    scoped(counts_sql, [&](Statement& select) {
      select.Step();
      counts.tests = select.ColumnInt64(0);
      counts.done = select.ColumnInt64(1);
      counts.failed = select.ColumnInt64(2);
      counts.pending = select.ColumnInt64(3);
      counts.running = select.ColumnInt64(4);
    });
  }
  // Results salvaged from faulty channels (schema/012_salvage.sql).
  scoped(IsWholeCatalogue(scope)
             ? "SELECT count(*) FROM result_salvage WHERE config_id = ?10 AND position = 0"
             : "WITH " + ScopeCte(scope) +
                   " SELECT count(*) FROM scope WHERE EXISTS (SELECT 1 FROM result_salvage AS rs "
                   "WHERE rs.test_id = scope.test_id AND rs.config_id = ?10 AND rs.position = 0)",
         [&](Statement& select) {
           select.Step();
           counts.salvaged = select.ColumnInt64(0);
         });
  scoped("WITH " + ScopeCte(scope) +
             " SELECT t.external_id, coalesce(j.last_error, '') FROM jobs AS j "
             "JOIN scope ON scope.test_id = j.test_id JOIN tests AS t ON t.id = j.test_id "
             "WHERE j.config_id = ?10 AND j.state = 'failed' ORDER BY t.external_id",
         [&](Statement& select) {
           while (select.Step()) counts.failures.push_back({select.ColumnText(0), select.ColumnText(1)});
         });
  transaction.Commit();
  return counts;
}

std::vector<VersionCount> JobQueue::ReadVersionCounts(const JobScope& scope) {
  // Over the whole catalogue, the results are counted in the order of the
  // index results_by_config_version (schema/014_catalogue_scale.sql) and the
  // failures of each config through jobs_by_config_state, never sorted row by row.
  const std::string counts_sql =
      (IsWholeCatalogue(scope)
           ? std::string(
                 "WITH computed AS (SELECT config_id, napkin_version, count(*) AS result, 0 AS failure "
                 "FROM results GROUP BY config_id, napkin_version "
                 "UNION ALL SELECT j.config_id, j.napkin_version, 0, count(*) FROM configs AS c "
                 "CROSS JOIN jobs AS j ON j.config_id = c.id AND j.state = 'failed' "
                 "GROUP BY j.config_id, j.napkin_version) ")
           : "WITH " + ScopeCte(scope) +
                 ", computed AS ("
                 "SELECT r.config_id, r.napkin_version, 1 AS result, 0 AS failure FROM results AS r "
                 "WHERE r.test_id IN (SELECT test_id FROM scope) "
                 "UNION ALL SELECT j.config_id, j.napkin_version, 0, 1 FROM jobs AS j "
                 "WHERE j.state = 'failed' AND j.test_id IN (SELECT test_id FROM scope)) ") +
      "SELECT c.id, c.name, c.config_hash, computed.napkin_version, sum(computed.result), "
      "sum(computed.failure) FROM computed JOIN configs AS c ON c.id = computed.config_id "
      "GROUP BY c.id, computed.napkin_version "
      "ORDER BY c.id, computed.napkin_version IS NOT NULL, computed.napkin_version";
  auto select = connection_.Prepare(counts_sql);
  BindJobScope(*select, scope);
  std::vector<VersionCount> counts;
  while (select->Step()) {
    VersionCount count;
    count.config_id = ConfigId{select->ColumnInt64(0)};
    count.config_name = select->ColumnText(1);
    count.config_hash = select->ColumnText(2);
    count.napkin_version = select->ColumnOptionalText(3);
    count.results = select->ColumnInt64(4);
    count.failed = select->ColumnInt64(5);
    counts.push_back(std::move(count));
  }
  return counts;
}

}  // namespace napkin::db
