-- napkin catalogue, schema version 5: honest conditioning (docs/formats.md
-- "Conditioning record", docs/algorithms.md "Signal conditioning").
--
-- raw_channels.prefiltered_cfc: the CFC class the imported file records the
-- channel as already filtered at (ISO-MME "Channel frequency class" / filter
-- letter, UDS-1992 FCUT); NULL = raw or not recorded (every channel imported
-- before this version, and every CSV channel).
--
-- result_conditioning: what conditioning did to each channel of a result, one
-- row per column of the test's signals (`position`), replaced with the result:
-- the filter applied (`filter` in words, `filter_cfc` NULL = none), the
-- prefilter the file records, the bias subtracted (in the channel's unit;
-- bias_t1_s / bias_t2_s the first and last sample averaged, NULL = no bias
-- removed) and the time shift. Results computed before this version have no
-- rows: `run --force` recomputes them.

ALTER TABLE raw_channels ADD COLUMN prefiltered_cfc REAL CHECK (prefiltered_cfc IS NULL OR prefiltered_cfc > 0);

CREATE TABLE result_conditioning (
  id              INTEGER PRIMARY KEY,
  test_id         INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id       INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  position        INTEGER NOT NULL CHECK (position >= 0),
  channel         TEXT NOT NULL,
  filter          TEXT NOT NULL,
  filter_cfc      REAL,
  prefiltered_cfc REAL,
  bias_removed    REAL,
  bias_t1_s       REAL,
  bias_t2_s       REAL,
  time_shift_s    REAL,
  UNIQUE (test_id, config_id, position)
);

-- `napkin query conditioning`: the conditioning of each test's latest result.
CREATE VIEW v_conditioning AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       c.channel, rc.unit AS unit, c.filter, c.filter_cfc, c.prefiltered_cfc,
       c.bias_removed, c.bias_t1_s, c.bias_t2_s, c.time_shift_s, c.position
FROM result_conditioning AS c
JOIN v_latest_results AS r ON r.test_id = c.test_id AND r.config_id = c.config_id
JOIN tests AS t ON t.id = c.test_id
LEFT JOIN series AS s ON s.id = t.series_id
LEFT JOIN raw_channels AS rc ON rc.test_id = c.test_id AND rc.slot = c.channel;
