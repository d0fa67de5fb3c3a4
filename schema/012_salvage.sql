-- napkin catalogue, schema version 12: salvaged results (docs/formats.md
-- "Salvage record", docs/algorithms.md "Faulty channels").
--
-- result_salvage: what salvage did to the faulty channels of a result
-- computed with a processing config whose screening.salvage is exclude or
-- repair, one row per channel (`position`), replaced with the result: the
-- fault (dropout, stuck, clipped, spike, flipped, swapped, inconsistent),
-- the action (excluded, inverted, swapped back, replaced), the swap's
-- partner, the fault's interval (t1_s, t2_s: its first and last faulty
-- sample, after the time shift), the samples replaced by the rigid-body
-- prediction, and per result the RMS rigid-body residual before and after
-- (g; NULL before when the recorded channels could not be solved) and the
-- channels the result was solved from. A result without rows comes from
-- the recorded channels as they are (every result stored before this
-- version).
--
-- `napkin query tests` and `query criteria` gain the column `salvaged` (1 =
-- the test's latest result is salvaged, 0 = not, NULL = no result), so
-- `--where "salvaged=0"` keeps the results of recorded channels only.

CREATE TABLE result_salvage (
  id                    INTEGER PRIMARY KEY,
  test_id               INTEGER NOT NULL REFERENCES tests(id) ON DELETE CASCADE,
  config_id             INTEGER NOT NULL REFERENCES configs(id) ON DELETE CASCADE,
  position              INTEGER NOT NULL CHECK (position >= 0),
  mode                  TEXT NOT NULL CHECK (mode IN ('exclude', 'repair')),
  channel               TEXT NOT NULL,
  fault                 TEXT NOT NULL,
  action                TEXT NOT NULL,
  partner               TEXT,
  t1_s                  REAL,
  t2_s                  REAL,
  samples_replaced      INTEGER NOT NULL CHECK (samples_replaced >= 0),
  rms_residual_before_g REAL,
  rms_residual_after_g  REAL,
  channels_used         INTEGER NOT NULL,
  channels_total        INTEGER NOT NULL,
  UNIQUE (test_id, config_id, position)
);

DROP VIEW v_tests;

CREATE VIEW v_tests AS
SELECT t.external_id AS test_id,
       s.name        AS series,
       t.variant     AS variant,
       a.name        AS array,
       t.source_path AS source_path,
       t.content_hash AS content_hash,
       t.imported_at AS imported_at,
       json_extract(t.metadata_json, '$.test.position')    AS position,
       json_extract(t.metadata_json, '$.test.test_number') AS test_number,
       json_extract(t.metadata_json, '$.test.title')       AS title,
       json_extract(t.metadata_json, '$.test.vehicle')     AS vehicle,
       json_extract(t.metadata_json, '$.test.dummy')       AS dummy,
       json_extract(t.metadata_json, '$.test.date')        AS test_date,
       json_extract(t.metadata_json, '$.test.laboratory')  AS laboratory,
       (SELECT EXISTS (SELECT 1 FROM result_salvage AS rs WHERE rs.test_id = lr.test_id AND rs.config_id = lr.config_id)
        FROM v_latest_results AS lr WHERE lr.test_id = t.id) AS salvaged
FROM tests AS t
JOIN arrays AS a ON a.id = t.array_id
LEFT JOIN series AS s ON s.id = t.series_id;

DROP VIEW v_criteria;

CREATE VIEW v_criteria AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.hic15, r.hic15_t1_s, r.hic15_t2_s,
       r.hic36, r.hic36_t1_s, r.hic36_t2_s,
       r.hic, r.hic_t1_s, r.hic_t2_s,
       r.peak_acc_g, r.a3ms_g, r.hic_d,
       r.peak_omega_x_radps, r.peak_omega_y_radps, r.peak_omega_z_radps,
       r.peak_omega_radps, r.peak_alpha_radps2,
       r.bric, r.damage,
       r.final_quat_w, r.final_quat_x, r.final_quat_y, r.final_quat_z,
       r.final_roll_deg, r.final_pitch_deg, r.final_yaw_deg,
       r.final_pos_x_m, r.final_pos_y_m, r.final_pos_z_m,
       r.max_rotation_deg,
       EXISTS (SELECT 1 FROM result_salvage AS rs WHERE rs.test_id = r.test_id AND rs.config_id = r.config_id)
         AS salvaged
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;
