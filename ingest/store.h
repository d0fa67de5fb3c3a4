#pragma once
// The one store sequence of a test (import, synth, tests): array record,
// test record and raw channels in one catalogue transaction.
#include <optional>

#include "db/catalogue.h"
#include "engine/array_geometry.h"
#include "engine/signals.h"

namespace napkin::ingest {

// Stores a test whole or not at all: `array_record` (the record of `array`,
// records::MakeArrayRecord; deduplicated), `record` with its array_id set
// here, and `signals` as raw channels in the units `array` gives their
// slots. When the catalogue already holds a test of `record.content_hash`
// nothing is stored and nullopt is returned. Throws InputError, before
// anything is written, when a channel is not a slot of `array`. With
// `replacing`, that test (the older content of the same source) is removed
// in the same transaction: the catalogue holds the old test or the new one,
// never neither.
std::optional<db::TestId> StoreTest(db::Catalogue& catalogue, const engine::ArrayGeometry& array,
                                    const db::ArrayRow& array_record, db::TestRow record,
                                    const engine::TestSignals& signals,
                                    std::optional<db::TestId> replacing = std::nullopt);

}  // namespace napkin::ingest
