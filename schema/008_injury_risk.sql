-- napkin catalogue, schema version 8: injury risks (docs/algorithms.md "Injury
-- risk", engine/injury_risk.h) are stored summary fields: P(AIS 3+) from HIC15
-- (NHTSA NCAP), P(AIS 4+) from HIC36 (Prasad-Mertz), P(AIS 3+) and P(AIS 4+)
-- from BrIC (Takhounts et al. 2013). The columns are appended to `results`
-- (hence last in engine::SummaryFields()); `napkin query risk` reads v_risk.
-- Results computed before this version get the risks of their stored criteria
-- from the engine's own curves (the SQL function napkin_injury_risk, which
-- db/migrate.cpp registers while migrating), so they need not be recomputed;
-- a NULL criterion (BrIC of an acceleration-only array) gives a NULL risk.

ALTER TABLE results ADD COLUMN hic15_p_ais3 REAL;
ALTER TABLE results ADD COLUMN hic36_p_ais4 REAL;
ALTER TABLE results ADD COLUMN bric_p_ais3 REAL;
ALTER TABLE results ADD COLUMN bric_p_ais4 REAL;
UPDATE results SET
  hic15_p_ais3 = napkin_injury_risk('hic15_p_ais3', hic15),
  hic36_p_ais4 = napkin_injury_risk('hic36_p_ais4', hic36),
  bric_p_ais3 = napkin_injury_risk('bric_p_ais3', bric),
  bric_p_ais4 = napkin_injury_risk('bric_p_ais4', bric);

CREATE VIEW v_risk AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       r.hic15_p_ais3, r.hic36_p_ais4, r.bric_p_ais3, r.bric_p_ais4
FROM v_latest_results AS r
JOIN tests AS t ON t.id = r.test_id
LEFT JOIN series AS s ON s.id = t.series_id;
