-- napkin catalogue, schema version 11: the test named by `correlate
-- --reference-test` is the reference curve (docs/formats.md "Correlation
-- ratings").
--
-- Before version 11 a test-against-test rating took --test's channel as the
-- reference and the --reference-test's as the candidate, while its
-- `reference` column named the latter: the roles were the wrong way round,
-- and corridor, magnitude and slope are not symmetric. Those ratings cannot
-- be recomputed here; they are marked: `reference` says so, and their
-- reference_key ("test-swapped:ID") is no longer the identity of a rating
-- made now, which is stored beside them. A test rated against itself is the
-- same either way and is left as it is.

UPDATE correlations
SET reference = reference || ' (rated before schema 11 with the roles swapped: this test was the candidate)',
    reference_key = 'test-swapped:' || substr(reference_key, length('test:') + 1)
WHERE reference_kind = 'test' AND reference_test_id IS NOT test_id;
