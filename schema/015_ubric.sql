-- napkin catalogue, schema version 15: UBrIC, the universal brain injury
-- criterion (Gabler, Crandall, Panzer 2018; docs/algorithms.md "Injury
-- criteria", engine/ubric.h), is a stored summary field. The column is
-- appended to `results` (hence last in engine::SummaryFields()); `napkin
-- query` generates its SELECT from that table (db/catalogue_query.cpp), so no
-- view is redefined, and v_latest_results (`r.*`) shows it to plain sqlite3.
-- UBrIC needs the peak angular acceleration of each body axis, which earlier
-- results do not store: their ubric stays NULL until the test is run again.

ALTER TABLE results ADD COLUMN ubric REAL;
