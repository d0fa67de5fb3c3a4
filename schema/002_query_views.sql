-- napkin catalogue, schema version 2: views for `napkin query` and for plain
-- sqlite3. Column names are the query contract (docs/formats.md "Per-test summary
-- fields"). A test may have results under several configs; the views show
-- its most recently written result (largest results.id).

CREATE VIEW v_latest_results AS
SELECT r.*
FROM results AS r
WHERE r.id = (SELECT max(latest.id) FROM results AS latest WHERE latest.test_id = r.test_id);

CREATE VIEW v_tests AS
SELECT t.external_id AS test_id,
       s.name        AS series,
       t.variant     AS variant,
       a.name        AS array,
       t.source_path AS source_path,
       t.content_hash AS content_hash,
       t.imported_at AS imported_at
FROM tests AS t
JOIN arrays AS a ON a.id = t.array_id
LEFT JOIN series AS s ON s.id = t.series_id;

CREATE VIEW v_hic AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.hic15, r.hic15_t1_s, r.hic15_t2_s,
       r.hic36, r.hic36_t1_s, r.hic36_t2_s,
       r.hic, r.hic_t1_s, r.hic_t2_s,
       r.peak_acc_g, r.a3ms_g
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;

CREATE VIEW v_rotation AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.peak_omega_x_radps, r.peak_omega_y_radps, r.peak_omega_z_radps,
       r.peak_omega_radps, r.peak_alpha_radps2,
       r.bric, r.damage,
       r.final_quat_w, r.final_quat_x, r.final_quat_y, r.final_quat_z,
       r.final_roll_deg, r.final_pitch_deg, r.final_yaw_deg,
       r.final_pos_x_m, r.final_pos_y_m, r.final_pos_z_m,
       r.max_rotation_deg
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;

CREATE VIEW v_criteria AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.hic15, r.hic15_t1_s, r.hic15_t2_s,
       r.hic36, r.hic36_t1_s, r.hic36_t2_s,
       r.hic, r.hic_t1_s, r.hic_t2_s,
       r.peak_acc_g, r.a3ms_g,
       r.peak_omega_x_radps, r.peak_omega_y_radps, r.peak_omega_z_radps,
       r.peak_omega_radps, r.peak_alpha_radps2,
       r.bric, r.damage,
       r.final_quat_w, r.final_quat_x, r.final_quat_y, r.final_quat_z,
       r.final_roll_deg, r.final_pitch_deg, r.final_yaw_deg,
       r.final_pos_x_m, r.final_pos_y_m, r.final_pos_z_m,
       r.max_rotation_deg
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;

-- Findings under the config of the test's latest result; for a test without
-- any result (e.g. it failed), those of its most recently written findings.
CREATE VIEW v_quality AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       f.check_name AS "check", f.channel AS channel,
       f.severity AS severity, f.detail AS detail
FROM findings AS f
JOIN tests AS t ON t.id = f.test_id
LEFT JOIN series AS s ON s.id = t.series_id
WHERE f.config_id = coalesce(
  (SELECT r.config_id FROM results AS r WHERE r.test_id = f.test_id ORDER BY r.id DESC LIMIT 1),
  (SELECT latest.config_id FROM findings AS latest WHERE latest.test_id = f.test_id
   ORDER BY latest.id DESC LIMIT 1));

CREATE VIEW v_jobs AS
SELECT t.external_id AS test_id, c.name AS config, c.config_hash AS config_hash,
       j.state, j.attempts, j.last_error, j.lease_owner, j.lease_expires_at,
       j.started_at, j.finished_at, j.duration_s
FROM jobs AS j
JOIN tests AS t ON t.id = j.test_id
JOIN configs AS c ON c.id = j.config_id;
