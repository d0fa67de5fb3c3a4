-- napkin catalogue, schema version 16: the inbox's failures of tests that
-- never became a row of `tests` (docs/serve.md "Inbox", docs/formats.md
-- "Inbox failures").
--
-- inbox_failures: one row per test under `napkin serve --inbox` that failed
-- before it was imported: a bad napkin.json sidecar above it (`sidecar`,
-- the sentence names the sidecar file), a series or variant folder whose
-- name cannot be one (`folder`), or a file the importer could not read
-- (`import failed`). `source` is the test's file or folder as the inbox
-- found it; `signature` the sizes and modification times of its files and
-- sidecars when it failed: the inbox tries the test again only when they
-- change, also after a restart, and says the failure once. The row is the
-- test's latest failure: replaced by a newer one, removed when the test is
-- imported (or found already in the catalogue). A test that was imported
-- and then failed in processing is a failed job, not a row here.

CREATE TABLE inbox_failures (
  source    TEXT PRIMARY KEY,
  test_name TEXT NOT NULL,
  series    TEXT NOT NULL,
  variant   TEXT NOT NULL,
  kind      TEXT NOT NULL CHECK (kind IN ('sidecar', 'folder', 'import failed')),
  error     TEXT NOT NULL,
  signature TEXT NOT NULL,
  failed_at TEXT NOT NULL
);
