#include "app/table_output.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <type_traits>
#include <vector>

#include "common/error.h"
#include "util/text.h"

namespace napkin::app {
namespace {

bool IsNumber(const db::Cell& cell) {
  return std::holds_alternative<std::int64_t>(cell) || std::holds_alternative<double>(cell);
}

std::string HumanText(const db::Cell& cell) {
  return std::visit(
      [](const auto& value) -> std::string {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "-";
        } else if constexpr (std::is_same_v<T, std::int64_t>) {
          return std::to_string(value);
        } else if constexpr (std::is_same_v<T, double>) {
          return fmt::format("{:.6g}", value);
        } else {
          return util::EscapeControl(value);  // no terminal escape sequence reaches the screen
        }
      },
      cell);
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

std::string CsvText(const db::Cell& cell) {
  return std::visit(
      [](const auto& value) -> std::string {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "";
        } else if constexpr (std::is_same_v<T, std::int64_t>) {
          return std::to_string(value);
        } else if constexpr (std::is_same_v<T, double>) {
          return std::isfinite(value) ? util::FormatNumber(value) : "";
        } else {
          return CsvField(util::EscapeControl(value));
        }
      },
      cell);
}

nlohmann::ordered_json JsonValue(const db::Cell& cell) {
  return std::visit(
      [](const auto& value) -> nlohmann::ordered_json {
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, double>) {
          if (!std::isfinite(value)) return nullptr;
          return value;
        } else {
          return value;
        }
      },
      cell);
}

std::string HumanTable(const db::Table& table) {
  const std::size_t columns = table.columns.size();
  std::vector<std::vector<std::string>> text(table.rows.size());
  std::vector<std::size_t> width(columns);
  for (std::size_t c = 0; c < columns; ++c) width[c] = table.columns[c].size();
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    for (std::size_t c = 0; c < columns; ++c) {
      text[r].push_back(HumanText(table.rows[r][c]));
      width[c] = std::max(width[c], text[r][c].size());
    }
  }
  // Right-align a column when it holds numbers (first non-NULL cell decides).
  std::vector<bool> right(columns, false);
  for (std::size_t c = 0; c < columns; ++c) {
    for (const auto& row : table.rows) {
      if (std::holds_alternative<std::monostate>(row[c])) continue;
      right[c] = IsNumber(row[c]);
      break;
    }
  }
  auto line = [&](const auto& cell_text) {
    std::string out;
    for (std::size_t c = 0; c < columns; ++c) {
      if (c > 0) out += "  ";
      const std::string& cell = cell_text(c);
      const std::string pad(width[c] - cell.size(), ' ');
      out += right[c] ? pad + cell : (c + 1 < columns ? cell + pad : cell);
    }
    return out + "\n";
  };
  std::string out = line([&](std::size_t c) -> const std::string& { return table.columns[c]; });
  std::vector<std::string> rules(columns);
  for (std::size_t c = 0; c < columns; ++c) rules[c] = std::string(width[c], '-');
  out += line([&](std::size_t c) -> const std::string& { return rules[c]; });
  for (const auto& row_text : text)
    out += line([&](std::size_t c) -> const std::string& { return row_text[c]; });
  if (table.rows.empty()) out += "(no rows)\n";
  return out;
}

}  // namespace

TableFormat ParseTableFormat(std::string_view text) {
  if (text == "table") return TableFormat::kTable;
  if (text == "csv") return TableFormat::kCsv;
  if (text == "json") return TableFormat::kJson;
  throw InputError("unknown output format '" + std::string(text) + "' (use table, csv or json).");
}

nlohmann::ordered_json TableRowJson(const db::Table& table, const std::vector<db::Cell>& row) {
  nlohmann::ordered_json object = nlohmann::ordered_json::object();
  for (std::size_t c = 0; c < row.size(); ++c) object[table.columns[c]] = JsonValue(row[c]);
  return object;
}

std::string FormatTable(const db::Table& table, TableFormat format) {
  switch (format) {
    case TableFormat::kTable:
      return HumanTable(table);
    case TableFormat::kCsv: {
      std::string out;
      for (std::size_t c = 0; c < table.columns.size(); ++c)
        out.append(c > 0 ? "," : "").append(CsvField(table.columns[c]));
      out += "\n";
      for (const auto& row : table.rows) {
        for (std::size_t c = 0; c < row.size(); ++c) out.append(c > 0 ? "," : "").append(CsvText(row[c]));
        out += "\n";
      }
      return out;
    }
    case TableFormat::kJson: {
      nlohmann::ordered_json rows = nlohmann::ordered_json::array();
      for (const auto& row : table.rows) rows.push_back(TableRowJson(table, row));
      // Text an older napkin stored may not be UTF-8 (docs/formats.md "Text
      // encoding"): its bad bytes become U+FFFD instead of failing the answer.
      return rows.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
    }
  }
  return {};
}

}  // namespace napkin::app
