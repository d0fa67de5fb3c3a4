-- napkin catalogue, schema version 10: a rating says the model units it was
-- rated under (docs/formats.md "Correlation ratings").
--
-- An LS-DYNA curve's numbers carry no units: `correlate --model-units` gives
-- them, and the same curve under m,s,kg and mm,s,kg are two ratings with two
-- answers. model_units holds the units given ("mm,s,kg"; null for a CSV
-- model, whose header gives its units, for the other kinds, and for the
-- ratings stored before version 10, whose units were not recorded), and is
-- part of the rating's identity through reference_key
-- ("model:SHA-256:COLUMN:units=mm,s,kg"), so a rating under other units is
-- another row, never a replacement.

ALTER TABLE correlations ADD COLUMN model_units TEXT;

DROP VIEW v_correlation;
CREATE VIEW v_correlation AS
SELECT t.external_id AS test_id, s.name AS series, t.variant AS variant,
       c.channel, c.reference_kind, c.reference, c.model_file, c.model_sha256, c.model_column,
       c.model_units, rt.external_id AS reference_test, c.edition, c.start_s, c.end_s,
       c.corridor, c.phase, c.magnitude, c.slope, c.overall, c.grade, c.shift_s,
       cf.name AS config, c.rated_at,
       c.config_id AS config_id
FROM correlations AS c
JOIN tests AS t ON t.id = c.test_id
JOIN configs AS cf ON cf.id = c.config_id
LEFT JOIN series AS s ON s.id = t.series_id
LEFT JOIN tests AS rt ON rt.id = c.reference_test_id;
