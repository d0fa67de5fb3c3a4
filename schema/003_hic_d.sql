-- napkin catalogue, schema version 3: the FMVSS No. 201 free-motion headform
-- HIC(d) = 0.75446 HIC36 + 166.4 (docs/algorithms.md "Injury criteria") is a
-- stored summary field. The column is appended to `results` (hence last in
-- engine::SummaryFields()); the views show it after the other HIC fields.
-- Results computed before this version get it from their stored HIC36 by the
-- same double arithmetic the engine uses, so they need not be recomputed.

ALTER TABLE results ADD COLUMN hic_d REAL;
UPDATE results SET hic_d = 0.75446 * hic36 + 166.4 WHERE hic36 IS NOT NULL;

DROP VIEW v_hic;
DROP VIEW v_criteria;

CREATE VIEW v_hic AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.hic15, r.hic15_t1_s, r.hic15_t2_s,
       r.hic36, r.hic36_t1_s, r.hic36_t2_s,
       r.hic, r.hic_t1_s, r.hic_t2_s,
       r.peak_acc_g, r.a3ms_g, r.hic_d
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;

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
       r.max_rotation_deg
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;
