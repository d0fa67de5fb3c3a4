-- napkin catalogue, schema version 4: the test-level information read from
-- ISO-MME .mme files and UDS-1992 headers (docs/formats.md "Test
-- information"), stored by import in tests.metadata_json under "test", is
-- shown by `napkin query tests`: the dummy's position (ISO/TS 13499 test
-- object and position, "11", "13"; UDS-1992 SENLOC) and what the files say
-- about the test. NULL where the files record none (and for tests imported
-- before this version, CSV files and synthetic tests).

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
       json_extract(t.metadata_json, '$.test.laboratory')  AS laboratory
FROM tests AS t
JOIN arrays AS a ON a.id = t.array_id
LEFT JOIN series AS s ON s.id = t.series_id;
