-- napkin catalogue, schema version 6: derived-channel storage is a processing
-- choice (docs/formats.md "Derived-channel storage"). derived_channels.encoding
-- names how `samples` holds the values: 'float64' (IEEE-754 binary64,
-- little-endian, 8 bytes each) or 'float32' (binary32, little-endian, 4 bytes
-- each, rounded to nearest). A result stored with storage "none" has no rows.
-- SQLite cannot alter a CHECK constraint, so the table is rebuilt (create new,
-- copy, drop old, rename; the migration runs with foreign keys off). Every
-- row written before this version is float64.

CREATE TABLE derived_channels_v6 (
  id           INTEGER PRIMARY KEY,
  test_id      INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id    INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  name         TEXT NOT NULL,
  dt_s         REAL,
  t0_s         REAL,
  sample_count INTEGER NOT NULL CHECK (sample_count >= 0),
  encoding     TEXT NOT NULL CHECK (encoding IN ('float64', 'float32')),
  samples      BLOB NOT NULL CHECK (length(samples) = (CASE encoding WHEN 'float32' THEN 4 ELSE 8 END) * sample_count),
  UNIQUE (test_id, config_id, name)
);

INSERT INTO derived_channels_v6 (id, test_id, config_id, name, dt_s, t0_s, sample_count, encoding, samples)
  SELECT id, test_id, config_id, name, dt_s, t0_s, sample_count, 'float64', samples FROM derived_channels;

DROP TABLE derived_channels;
ALTER TABLE derived_channels_v6 RENAME TO derived_channels;
