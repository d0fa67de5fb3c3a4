#pragma once
// The catalogue's SQL migrations (schema/NNN_*.sql), embedded into the binary
// at build time by cmake/embed_files.cmake (schema/CMakeLists.txt). Migration
// N brings a catalogue from PRAGMA user_version N-1 to N.
#include <span>
#include <string_view>

namespace napkin::schema {

struct Migration {
  int version = 0;        // the NNN prefix of the file name: 1, 2, ...
  std::string_view name;  // file name, e.g. "001_catalogue.sql"
  std::string_view sql;   // the file's contents
};

// All embedded migrations, ordered by version, numbered 1..N without gaps.
std::span<const Migration> Migrations();

}  // namespace napkin::schema
