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

namespace {

// A JobScope: the test filter (catalogue_internal.h) plus the shard, ?4
// (count) and ?5 (index).
constexpr const char* kShardTerms = "(?4 IS NULL OR t.id % ?4 = ?5)";

}  // namespace

namespace internal {

// The tests of a JobScope: parameters ?1..?5.
std::string JobScopeCte() {
  return std::string(
             "scope AS (SELECT t.id AS test_id FROM tests AS t LEFT JOIN series AS s ON s.id = t.series_id "
             "WHERE ") +
         internal::kTestFilterTerms + " AND " + kShardTerms + ")";
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

}  // namespace internal

namespace {

using internal::BindJobScope;

std::string ScopeCte() { return internal::JobScopeCte(); }

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
  {
    // Tests without a job for this config and without a result (a result
    // without a job comes from a merged shard catalogue: it is done).
    static const std::string kInsert =
        "WITH " + ScopeCte() +
        " INSERT INTO jobs (test_id, config_id, state, enqueued_at) "
        "SELECT scope.test_id, ?10, 'queued', ?11 FROM scope "
        "WHERE NOT EXISTS (SELECT 1 FROM jobs AS j WHERE j.test_id = scope.test_id AND j.config_id = ?10) "
        "AND (?12 OR NOT EXISTS (" +
        internal::UpToDateResult("scope.test_id") + "))";
    queued += queue(kInsert);
  }
  {
    // Existing jobs: failed ones, done ones whose result is gone, and with
    // `force` every done one. Running jobs are left to their worker (or to
    // lease expiry); earlier results are never deleted here.
    static const std::string kRequeue =
        "WITH " + ScopeCte() +
        " UPDATE jobs SET state = 'queued', enqueued_at = ?11, lease_owner = NULL, lease_expires_at = NULL, "
        "started_at = NULL, finished_at = NULL, duration_s = NULL "
        "WHERE config_id = ?10 AND test_id IN (SELECT test_id FROM scope) AND ("
        "state = 'failed' OR (state = 'done' AND (?12 OR NOT EXISTS (" +
        internal::UpToDateResult("jobs.test_id") + "))))";
    queued += queue(kRequeue);
  }
  transaction.Commit();
  return queued;
}

std::vector<Job> JobQueue::ClaimJobs(ConfigId config, const std::string& owner, int max_jobs,
                                     double lease_seconds, const JobScope& scope) {
  if (max_jobs <= 0) return {};
  if (!(lease_seconds > 0.0)) throw std::invalid_argument("ClaimJobs: lease_seconds must be positive");
  const double now = clock_();
  Transaction transaction(connection_);  // BEGIN IMMEDIATE: claims are serialised
  static const std::string kClaim =
      "WITH " + ScopeCte() +
      " UPDATE jobs SET state = 'running', lease_owner = ?11, lease_expires_at = ?12 + ?13, started_at = "
      "?12, "
      "finished_at = NULL, duration_s = NULL, attempts = attempts + 1 "
      "WHERE id IN (SELECT id FROM jobs WHERE config_id = ?10 AND test_id IN (SELECT test_id FROM scope) AND "
      "(state = 'queued' OR (state = 'running' AND lease_expires_at <= ?12)) ORDER BY id LIMIT ?14) "
      "RETURNING id, test_id, attempts";
  auto claim = connection_.Prepare(kClaim);
  BindConfigScope(*claim, config, scope);
  claim->Bind(11, owner);
  claim->Bind(12, now);
  claim->Bind(13, lease_seconds);
  claim->Bind(14, max_jobs);
  std::vector<Job> jobs;
  while (claim->Step())
    jobs.push_back({JobId{claim->ColumnInt64(0)}, TestId{claim->ColumnInt64(1)}, config,
                    static_cast<int>(claim->ColumnInt64(2))});
  transaction.Commit();
  std::sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.id < b.id; });
  return jobs;
}

std::vector<std::string> JobQueue::ReadLeaseOwners(ConfigId config, const JobScope& scope) {
  static const std::string kOwners =
      "WITH " + ScopeCte() +
      " SELECT DISTINCT lease_owner FROM jobs WHERE config_id = ?10 AND state = 'running' "
      "AND test_id IN (SELECT test_id FROM scope) ORDER BY lease_owner";
  auto select = connection_.Prepare(kOwners);
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
  {
    // A test's state: its job's, unless the job is done (or absent), in
    // which case it is done if a result exists and pending otherwise.
    static const std::string kCounts =
        "WITH " + ScopeCte() +
        ", states AS (SELECT CASE "
        "WHEN j.state IN ('queued', 'running', 'failed') THEN j.state "
        "WHEN EXISTS (SELECT 1 FROM results AS r WHERE r.test_id = scope.test_id AND r.config_id = ?10) THEN "
        "'done' "
        "ELSE 'queued' END AS state "
        "FROM scope LEFT JOIN jobs AS j ON j.test_id = scope.test_id AND j.config_id = ?10) "
        "SELECT count(*), coalesce(sum(state = 'done'), 0), coalesce(sum(state = 'failed'), 0), "
        "coalesce(sum(state = 'queued'), 0), coalesce(sum(state = 'running'), 0) FROM states";
    auto select = connection_.Prepare(kCounts);
    BindConfigScope(*select, config, scope);
    select->Step();
    counts.tests = select->ColumnInt64(0);
    counts.done = select->ColumnInt64(1);
    counts.failed = select->ColumnInt64(2);
    counts.pending = select->ColumnInt64(3);
    counts.running = select->ColumnInt64(4);
  }
  {
    // Results salvaged from faulty channels (schema/012_salvage.sql).
    static const std::string kSalvaged =
        "WITH " + ScopeCte() +
        " SELECT count(*) FROM scope WHERE EXISTS (SELECT 1 FROM result_salvage AS rs "
        "WHERE rs.test_id = scope.test_id AND rs.config_id = ?10 AND rs.position = 0)";
    auto select = connection_.Prepare(kSalvaged);
    BindConfigScope(*select, config, scope);
    select->Step();
    counts.salvaged = select->ColumnInt64(0);
  }
  {
    static const std::string kFailures =
        "WITH " + ScopeCte() +
        " SELECT t.external_id, coalesce(j.last_error, '') FROM jobs AS j "
        "JOIN scope ON scope.test_id = j.test_id JOIN tests AS t ON t.id = j.test_id "
        "WHERE j.config_id = ?10 AND j.state = 'failed' ORDER BY t.external_id";
    auto select = connection_.Prepare(kFailures);
    BindConfigScope(*select, config, scope);
    while (select->Step()) counts.failures.push_back({select->ColumnText(0), select->ColumnText(1)});
  }
  transaction.Commit();
  return counts;
}

std::vector<VersionCount> JobQueue::ReadVersionCounts(const JobScope& scope) {
  static const std::string kCounts =
      "WITH " + ScopeCte() +
      ", computed AS ("
      "SELECT r.config_id, r.napkin_version, 1 AS result, 0 AS failure FROM results AS r "
      "WHERE r.test_id IN (SELECT test_id FROM scope) "
      "UNION ALL SELECT j.config_id, j.napkin_version, 0, 1 FROM jobs AS j "
      "WHERE j.state = 'failed' AND j.test_id IN (SELECT test_id FROM scope)) "
      "SELECT c.id, c.name, c.config_hash, computed.napkin_version, sum(computed.result), "
      "sum(computed.failure) FROM computed JOIN configs AS c ON c.id = computed.config_id "
      "GROUP BY c.id, computed.napkin_version "
      "ORDER BY c.id, computed.napkin_version IS NOT NULL, computed.napkin_version";
  auto select = connection_.Prepare(kCounts);
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
