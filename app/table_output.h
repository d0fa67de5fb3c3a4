#pragma once
// Tables on stdout (`napkin query`, and any command with --format
// table,csv,json): aligned columns for people, RFC 4180 CSV and a JSON array
// of objects for programs.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "db/catalogue.h"

namespace napkin::app {

enum class TableFormat { kTable, kCsv, kJson };

// "table", "csv" or "json"; throws InputError otherwise.
TableFormat ParseTableFormat(std::string_view text);

// kTable: a header, a rule and one line per row; numbers right-aligned with 6
// significant digits, text left-aligned, NULL as "-"; "(no rows)" when empty.
// kCsv: a header line, then one line per row; numbers in their shortest exact
// form, NULL as an empty field, text quoted when it holds a comma, a quote
// or a line break.
// kJson: an array with one object per row, keys the column names in column
// order, numbers as numbers (non-finite ones and NULL as null), text as strings.
// Text cells of kTable and kCsv have their control characters escaped
// (util::EscapeControl: "\x1b", "\n", ...), so stored text can never
// send escape sequences to a terminal or break a CSV line; kJson escapes
// them as JSON does. Every form ends with a newline.
std::string FormatTable(const db::Table& table, TableFormat format);

// One row of `table` as kJson writes it: an object, keys the column names in
// column order. For a front end that puts rows inside a larger JSON answer
// (the service's test summary), so that no front end parses JSON text back.
nlohmann::ordered_json TableRowJson(const db::Table& table, const std::vector<db::Cell>& row);

}  // namespace napkin::app
