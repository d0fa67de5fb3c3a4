-- napkin catalogue, schema version 9: ISO/TS 18571 ratings (docs/algorithms.md
-- "Test against model: ISO/TS 18571"; `napkin correlate`, `napkin query
-- correlation`, docs/formats.md "Correlation ratings").
--
-- One row per rating of one channel of a test's result against a curve
-- (in the standard's words the test's channel is the reference curve, the
-- other the candidate; column `reference` names that other curve), of kind:
--   'model'         a model's curve: the file's SHA-256, its name and the column rated
--   'test'          another test's same channel (its latest result at rating time)
--   'variant-mean'  the mean curve of the test's variant in its series
--                   (`correlate --series S --variant V`)
-- with the parameters (edition, evaluation interval as evaluated) and the
-- scores. A rating belongs to the result it rated: the row refers to the
-- results row, so a result computed again (run --force, a merge) drops its
-- ratings, which no longer describe it. Rating again with the same
-- reference and parameters replaces the row (reference_key, UNIQUE).

CREATE TABLE correlations (
  id                INTEGER PRIMARY KEY AUTOINCREMENT,
  result_id         INTEGER NOT NULL REFERENCES results(id) ON DELETE CASCADE,
  test_id           INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id         INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  channel           TEXT NOT NULL,
  reference_kind    TEXT NOT NULL CHECK (reference_kind IN ('model', 'test', 'variant-mean')),
  reference         TEXT NOT NULL,   -- as shown: "head.k:curve 4", a test id, "mean of foam-a"
  reference_key     TEXT NOT NULL,   -- identity: "model:SHA-256:COLUMN", "test:ID", "variant-mean:S/V"
  model_file        TEXT,            -- the model file's name (no folder); 'model' only
  model_sha256      TEXT,            -- of the model file's bytes; 'model' only
  model_column      TEXT,            -- the curve rated; 'model' only
  reference_test_id INTEGER REFERENCES tests(id) ON DELETE CASCADE,  -- 'test' only
  reference_series  TEXT,            -- 'variant-mean' only
  reference_variant TEXT,            -- 'variant-mean' only
  edition           TEXT NOT NULL CHECK (edition IN ('2014', '2024')),
  start_s           REAL NOT NULL,
  end_s             REAL NOT NULL,
  corridor          REAL NOT NULL,
  phase             REAL NOT NULL,
  magnitude         REAL NOT NULL,
  slope             REAL NOT NULL,
  overall           REAL NOT NULL,
  grade             TEXT NOT NULL,
  shift_s           REAL NOT NULL,
  rated_at          TEXT NOT NULL,
  napkin_version    TEXT,
  UNIQUE (result_id, channel, reference_key, edition, start_s, end_s)
);
CREATE INDEX correlations_test ON correlations(test_id);

CREATE VIEW v_correlation AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       c.channel, c.reference_kind, c.reference, c.model_file, c.model_sha256, c.model_column,
       rt.external_id AS reference_test, c.edition, c.start_s, c.end_s,
       c.corridor, c.phase, c.magnitude, c.slope, c.overall, c.grade, c.shift_s,
       cf.name AS config, c.rated_at,
       c.config_id AS config_id
FROM correlations AS c
JOIN tests AS t ON t.id = c.test_id
JOIN configs AS cf ON cf.id = c.config_id
LEFT JOIN series AS s ON s.id = t.series_id
LEFT JOIN tests AS rt ON rt.id = c.reference_test_id;
