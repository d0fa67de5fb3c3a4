#pragma once
// The batch scheduler's job queue (README "Batch runs", docs/architecture.md): one row
// per (test, config) in the catalogue's `jobs` table, claimed under leases by
// workers with their own connection (jobs/scheduler.h), counted by `napkin
// status`.
//
// A JobQueue works on a Catalogue's connection and clock, so queue writes join
// the catalogue's transactions (a result and its job's completion commit
// together). Like a Transaction over its Connection it is a view: make one
// from a Catalogue that outlives it (a temporary Catalogue is refused).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "db/catalogue.h"
#include "db/sqlite.h"

namespace napkin::db {

enum class JobId : std::int64_t {};

// Tests whose key satisfies key % count == index (run --shard I/N; shard
// catalogues are copies of one catalogue, so keys agree).
struct Shard {
  int index = 0;
  int count = 1;
};

struct JobScope {
  TestFilter tests;
  std::optional<Shard> shard;
};

// A claimed job.
struct Job {
  JobId id{};
  TestId test_id{};
  ConfigId config_id{};
  int attempts = 0;  // claims so far, this one included
};

struct JobFailure {
  std::string test_id;  // external id
  std::string error;
};

// `napkin status`: every test in scope counted once by its state for a config.
struct StatusCounts {
  std::int64_t tests = 0;
  std::int64_t done = 0;  // a result exists and no new job is pending
  std::int64_t failed = 0;
  std::int64_t pending = 0;  // queued, or never enqueued and without a result
  std::int64_t running = 0;
  std::int64_t salvaged = 0;         // of the done: results from salvaged channels (result_salvage)
  std::vector<JobFailure> failures;  // ordered by test id
};

// `napkin status`: how many results (and failures) one napkin version computed
// under one config (docs/formats.md "Version string").
struct VersionCount {
  ConfigId config_id{};
  std::string config_name;
  std::string config_hash;
  std::optional<std::string> napkin_version;  // empty: computed before version tracking
  std::int64_t results = 0;                   // result rows
  std::int64_t failed = 0;                    // jobs whose last attempt failed under this version
};

class JobQueue {
 public:
  explicit JobQueue(Catalogue& catalogue);
  JobQueue(Catalogue&&) = delete;  // the queue would outlive its connection

  // Queues a job for every test in scope whose result for `config` is
  // missing (never computed, or its job is done but the result is gone) or
  // whose job failed; with `force`, also tests already done; with `outdated`
  // (run --outdated), also tests whose result was computed by another napkin
  // version than the catalogue's (Catalogue::napkin_version(); a result from
  // before version tracking, NULL, is another version). A config whose
  // JSON changed has a new hash, hence a new key: its tests are all missing
  // and earlier results under the old config stay. Returns the number of
  // jobs queued.
  std::int64_t EnqueueMissing(ConfigId config, const JobScope& scope = {}, bool force = false,
                              bool outdated = false);
  // Atomically (BEGIN IMMEDIATE) claims up to `max_jobs` jobs of `config`
  // (of the tests in `scope`) that are queued or whose lease has expired,
  // leasing them to `owner` for `lease_seconds`. Two workers never get the
  // same job while a lease holds. The queue is walked in key order on from
  // the last job this JobQueue claimed, and from the start again when fewer
  // than `max_jobs` are found there: a claim costs what it takes, not the
  // length of the queue (docs/architecture.md "Catalogues of a million tests").
  std::vector<Job> ClaimJobs(ConfigId config, const std::string& owner, int max_jobs, double lease_seconds,
                             const JobScope& scope = {});
  // The distinct owners of running jobs of `config` in `scope` (the scheduler
  // waits for them, or releases the leases of a worker it knows is dead).
  std::vector<std::string> ReadLeaseOwners(ConfigId config, const JobScope& scope = {});
  // Puts the running jobs of `config` leased to `owner` back in the queue
  // (their attempts stay counted); returns how many. For a worker known to
  // be dead, or one stopping with claimed jobs it will not process.
  std::int64_t ReleaseLeases(ConfigId config, const std::string& owner);
  // Extends a running job's lease; false when `owner` no longer holds it.
  bool RenewLease(JobId job, const std::string& owner, double lease_seconds);
  // Marks a running job done (records finish time and duration); false when
  // `owner` no longer holds it (its lease expired and another worker took it).
  bool CompleteJob(JobId job, const std::string& owner);
  // Marks a running job failed with `error`; false when `owner` no longer holds it.
  bool FailJob(JobId job, const std::string& owner, const std::string& error);
  StatusCounts ReadStatusCounts(ConfigId config, const JobScope& scope = {});
  // `napkin status`: the results and failed jobs of the tests in scope, counted by
  // config and by the napkin version that computed them; ordered by config key, then
  // version (NULL, before version tracking, first).
  std::vector<VersionCount> ReadVersionCounts(const JobScope& scope = {});

 private:
  Connection& connection_;                // the catalogue's
  const std::function<double()>& clock_;  // the catalogue's: epoch seconds
  const std::string& napkin_version_;     // the catalogue's: recorded with finished jobs
  ConfigId claim_config_{};               // the config of the last claim
  std::int64_t claim_after_ = 0;          // ... and the key of the last job it claimed
};

}  // namespace napkin::db
