#include "tests/support/db/results_dump.h"

#include <algorithm>
#include <cstdio>
#include <string_view>
#include <vector>

#include "db/catalogue.h"
#include "tests/support/db/catalogue_inspector.h"
#include "util/sha256.h"

namespace napkin::db {

namespace {

// What a key column names, as an SQL expression over the row alias r.
std::string NamedKey(const std::string& column) {
  if (column == "test_id") return "(SELECT external_id FROM tests WHERE id = r.test_id)";
  if (column == "config_id") return "(SELECT config_hash FROM configs WHERE id = r.config_id)";
  if (column == "series_id") return "(SELECT name FROM series WHERE id = r.series_id)";
  if (column == "array_id") return "(SELECT definition_hash FROM arrays WHERE id = r.array_id)";
  return "r.\"" + column + "\"";
}

bool LeftOut(const std::string& column) {
  const auto ends_with = [&](std::string_view suffix) {
    return column.size() >= suffix.size() &&
           column.compare(column.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  return column == "id" || ends_with("_at") || column == "duration_s" || column == "lease_owner" ||
         column == "attempts";
}

std::string Value(const Statement& row, int c) {
  switch (row.ColumnType(c)) {
    case SQLITE_NULL:
      return "NULL";
    case SQLITE_INTEGER:
      return std::to_string(row.ColumnInt64(c));
    case SQLITE_FLOAT: {
      char text[40];
      std::snprintf(text, sizeof text, "%a", row.ColumnDouble(c));
      return text;
    }
    case SQLITE_TEXT: {
      std::string quoted = "'";
      for (const char ch : row.ColumnText(c)) {
        if (ch == '\\') {
          quoted += "\\\\";
        } else if (ch == '\n') {
          quoted += "\\n";
        } else if (ch == '|') {
          quoted += "\\|";
        } else {
          quoted += ch;
        }
      }
      return quoted + "'";
    }
    default: {
      const auto blob = row.ColumnBlob(c);
      const std::string_view bytes(reinterpret_cast<const char*>(blob.data()), blob.size());
      return "blob:" + std::to_string(blob.size()) + ":" + util::Sha256Hex(bytes);
    }
  }
}

}  // namespace

std::string CanonicalResultsDump(const std::string& path) {
  CatalogueOptions options;
  options.read_only = true;
  Catalogue catalogue = Catalogue::Open(path, options);
  CatalogueInspector inspector(catalogue);
  Connection& connection = inspector.connection();
  std::string dump;
  for (const char* table : {"series", "arrays", "configs", "tests", "results", "findings",
                            "result_conditioning", "derived_channels", "jobs"}) {
    std::vector<std::string> names;
    std::string sql = "SELECT ";
    {
      Statement columns(connection.handle(),
                        std::string("SELECT name FROM pragma_table_info('") + table + "') ORDER BY cid");
      while (columns.Step()) {
        const std::string column = columns.ColumnText(0);
        if (LeftOut(column)) continue;
        sql += (names.empty() ? "" : ", ") + NamedKey(column);
        names.push_back(column);
      }
    }
    sql += std::string(" FROM \"") + table + "\" AS r";
    Statement rows(connection.handle(), sql);
    std::vector<std::string> lines;
    while (rows.Step()) {
      std::string line = table;
      for (int c = 0; c < rows.ColumnCount(); ++c)
        line += "|" + names[static_cast<std::size_t>(c)] + "=" + Value(rows, c);
      lines.push_back(std::move(line));
    }
    std::sort(lines.begin(), lines.end());
    for (const std::string& line : lines) dump += line + "\n";
  }
  return dump;
}

}  // namespace napkin::db
