-- napkin catalogue, schema version 14: indexes for catalogues of a million
-- tests (docs/architecture.md "Catalogues of a million tests"). Indexes only:
-- no row changes, and every query answers as before.
--
-- A claim (db/job_queue.cpp ClaimJobs) takes the first few queued jobs of a
-- config in key order. Version 1's index on (config_id, state,
-- lease_expires_at) orders a config's queued jobs by lease_expires_at (NULL
-- for every one of them) before their key, so SQLite could not read them in
-- key order from it and sorted the whole queue on every claim: `run` grew as
-- N^1.8. An index on (config_id, state) holds the key after them, so the
-- queued jobs of a config come in key order and a claim reads only the jobs
-- it takes; the expired leases of the running jobs (a few per worker) are
-- found through the same index.

DROP INDEX jobs_by_config_state;
CREATE INDEX jobs_by_config_state ON jobs(config_id, state);

-- `napkin status` counts the results of each config and napkin version
-- (db/job_queue.cpp ReadVersionCounts, ReadStatusCounts): from this index in
-- its order, where it read every result row and sorted them.
CREATE INDEX results_by_config_version ON results(config_id, napkin_version);
