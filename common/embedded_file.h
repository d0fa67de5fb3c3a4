#pragma once
// A file embedded into the binary at build time by cmake/embed_files.cmake:
// the SQL migrations (schema/migrations.h) and the HTML report's files
// (formats/report_assets.h).
#include <string_view>

namespace napkin {

struct EmbeddedFile {
  std::string_view name;   // the file's name, without its folder, e.g. "001_catalogue.sql"
  std::string_view bytes;  // its contents, verbatim
};

}  // namespace napkin
