-- napkin catalogue, schema version 7: provenance for reprocessing (docs/formats.md
-- "Version string", README "Batch runs").
--
-- results.napkin_version: the napkin version that computed the result
-- ("0.1.0+g1a2b3c4", common/version.h); with the result's config (configs.config_hash)
-- it says what produced the numbers. NULL for results computed before this version
-- ("unknown (before version tracking)"); `run --outdated` recomputes them.
--
-- jobs.napkin_version: the napkin version that finished the job (done or failed), so a
-- failure, like a result, names the version it happened under. NULL for jobs finished
-- before this version, and for queued and running jobs.

ALTER TABLE results ADD COLUMN napkin_version TEXT;
ALTER TABLE jobs ADD COLUMN napkin_version TEXT;
