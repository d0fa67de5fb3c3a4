-- napkin catalogue, schema version 1: the entities.
--
-- Conventions: every table has an integer primary key `id`; a column
-- `<entity>_id` references `<entities>.id`. The external test identifier
-- (the query contract's `test_id`, e.g. "v0001") is `tests.external_id`.
-- Times are text in ISO-8601 UTC ("2024-05-01T12:00:00.000Z") except the
-- job lease/timing columns, which are seconds since the Unix epoch (REAL) so
-- that lease expiry is a plain comparison. Signals are BLOBs of little-endian
-- IEEE-754 float64, `8 * sample_count` bytes. Floating-point result columns
-- are nullable because SQLite stores NaN as NULL; NULL reads back as NaN.

-- 'NAPK': marks the file as a napkin catalogue (checked on open).
PRAGMA application_id = 1312903243;

CREATE TABLE series (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL UNIQUE,
  description TEXT NOT NULL DEFAULT ''
);

-- Accelerometer array definitions, deduplicated by the hash of their
-- canonical JSON.
CREATE TABLE arrays (
  id              INTEGER PRIMARY KEY,
  name            TEXT NOT NULL,
  definition_json TEXT NOT NULL CHECK (json_valid(definition_json)),
  definition_hash TEXT NOT NULL UNIQUE
);

CREATE TABLE tests (
  id                  INTEGER PRIMARY KEY,
  external_id         TEXT NOT NULL UNIQUE,
  series_id           INTEGER REFERENCES series(id),
  variant             TEXT,
  metadata_json       TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(metadata_json)),
  array_id            INTEGER NOT NULL REFERENCES arrays(id),
  -- Initial state (report eq. 2.1-14/15): body-to-fixed R0 = Rx(phi) Ry(theta) Rz(psi).
  orientation_phi_rad   REAL NOT NULL DEFAULT 0,
  orientation_theta_rad REAL NOT NULL DEFAULT 0,
  orientation_psi_rad   REAL NOT NULL DEFAULT 0,
  velocity_x_mps      REAL NOT NULL DEFAULT 0,
  velocity_y_mps      REAL NOT NULL DEFAULT 0,
  velocity_z_mps      REAL NOT NULL DEFAULT 0,
  omega_x_radps       REAL NOT NULL DEFAULT 0,
  omega_y_radps       REAL NOT NULL DEFAULT 0,
  omega_z_radps       REAL NOT NULL DEFAULT 0,
  source_path         TEXT NOT NULL,
  -- Hash of the imported content: importing the same content twice is a no-op.
  content_hash        TEXT NOT NULL UNIQUE,
  imported_at         TEXT NOT NULL
);
CREATE INDEX tests_by_series ON tests(series_id, variant);

-- Raw channels of a test, one row per array slot, in the column order of the
-- test's signal matrix (`position`).
CREATE TABLE raw_channels (
  id           INTEGER PRIMARY KEY,
  test_id      INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  position     INTEGER NOT NULL CHECK (position >= 0),
  slot         TEXT NOT NULL,
  unit         TEXT NOT NULL,
  dt_s         REAL NOT NULL CHECK (dt_s > 0),
  t0_s         REAL NOT NULL,
  sample_count INTEGER NOT NULL CHECK (sample_count >= 0),
  samples      BLOB NOT NULL CHECK (length(samples) = 8 * sample_count),
  UNIQUE (test_id, slot),
  UNIQUE (test_id, position)
);

-- Processing configurations, deduplicated by the hash of their canonical
-- JSON. A changed configuration is a new row: results computed with the old
-- one stay in the catalogue.
CREATE TABLE configs (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL,
  config_json TEXT NOT NULL CHECK (json_valid(config_json)),
  config_hash TEXT NOT NULL UNIQUE,
  created_at  TEXT NOT NULL
);

-- Work items of the batch scheduler, one per (test, config). A worker claims
-- queued jobs, or running jobs whose lease has expired (a crashed worker),
-- atomically under BEGIN IMMEDIATE. `attempts` counts claims.
CREATE TABLE jobs (
  id               INTEGER PRIMARY KEY,
  test_id          INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id        INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  state            TEXT NOT NULL DEFAULT 'queued'
                   CHECK (state IN ('queued', 'running', 'done', 'failed')),
  attempts         INTEGER NOT NULL DEFAULT 0 CHECK (attempts >= 0),
  last_error       TEXT,
  lease_owner      TEXT,
  lease_expires_at REAL,
  enqueued_at      REAL NOT NULL,
  started_at       REAL,
  finished_at      REAL,
  duration_s       REAL,
  UNIQUE (test_id, config_id),
  CHECK (state <> 'running' OR (lease_owner IS NOT NULL AND lease_expires_at IS NOT NULL))
);
CREATE INDEX jobs_by_config_state ON jobs(config_id, state, lease_expires_at);

-- Per-test summary for one config: every field of the query contract
-- (docs/formats.md "Per-test summary fields"). AUTOINCREMENT keeps ids monotonic so
-- the most recently written result of a test is the one with the largest id.
CREATE TABLE results (
  id                 INTEGER PRIMARY KEY AUTOINCREMENT,
  test_id            INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id          INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  solver             TEXT NOT NULL,
  computed_at        TEXT NOT NULL,
  hic15              REAL, hic15_t1_s REAL, hic15_t2_s REAL,
  hic36              REAL, hic36_t1_s REAL, hic36_t2_s REAL,
  hic                REAL, hic_t1_s   REAL, hic_t2_s   REAL,
  peak_acc_g         REAL,
  a3ms_g             REAL,
  peak_omega_x_radps REAL, peak_omega_y_radps REAL, peak_omega_z_radps REAL,
  peak_omega_radps   REAL,
  peak_alpha_radps2  REAL,
  bric               REAL,
  damage             REAL,
  final_quat_w REAL, final_quat_x REAL, final_quat_y REAL, final_quat_z REAL,
  final_roll_deg REAL, final_pitch_deg REAL, final_yaw_deg REAL,
  final_pos_x_m REAL, final_pos_y_m REAL, final_pos_z_m REAL,
  max_rotation_deg   REAL,
  max_residual_mps2  REAL,
  UNIQUE (test_id, config_id)
);

-- Screening findings of a test under a config (may exist without a result,
-- e.g. for a test that failed because a channel is missing).
CREATE TABLE findings (
  id         INTEGER PRIMARY KEY,
  test_id    INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id  INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  position   INTEGER NOT NULL,
  check_name TEXT NOT NULL,
  channel    TEXT,
  severity   TEXT NOT NULL CHECK (severity IN ('info', 'warning', 'error')),
  detail     TEXT NOT NULL,
  UNIQUE (test_id, config_id, position)
);

-- Derived channels (solved kinematics), one row per named component.
CREATE TABLE derived_channels (
  id           INTEGER PRIMARY KEY,
  test_id      INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id    INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  name         TEXT NOT NULL,
  dt_s         REAL,
  t0_s         REAL,
  sample_count INTEGER NOT NULL CHECK (sample_count >= 0),
  samples      BLOB NOT NULL CHECK (length(samples) = 8 * sample_count),
  UNIQUE (test_id, config_id, name)
);
