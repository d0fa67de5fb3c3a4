#pragma once
// The content hashes that identify a test's content in the catalogue
// (tests.content_hash): importing or synthesising the same content twice
// stores it once. Existing catalogues hold these values: never change what
// they hash.
#include <string>

#include "db/catalogue.h"
#include "ingest/discovery.h"
#include "synth/synthetic_tests.h"

namespace napkin::ingest {

// The hash of an input file set: SHA-256 of the file (a kFile format: CSV,
// DTS SLICEWare CSV, zip), of the folder's files (kFolder: ISO-MME;
// formats::HashPath), or of a kFileGroup's file hashes in name order after
// "<format> group\n" (UDS-1992). Throws InputError naming an unreadable file.
std::string InputContentHash(const ImportInput& input);

// The hash of a synthetic test's content: its array record's hash, initial
// state, time base, slot names and the samples' bytes.
std::string SyntheticContentHash(const db::ArrayRow& array, const synth::SyntheticTest& test);

}  // namespace napkin::ingest
