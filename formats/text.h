#pragma once
// Small text helpers shared by the readers and writers: exact number
// formatting (std::to_chars), strict number parsing (std::from_chars),
// trimming, case-insensitive comparison and ISO-8859-1 -> UTF-8.
#include <optional>
#include <string>
#include <string_view>

namespace napkin::formats {

// Appends `value`: precision 0 = shortest text that reads back to the same
// double (exact round trip); otherwise like printf("%.<precision>g").
void AppendNumber(std::string& out, double value, int precision = 0);
std::string FormatNumber(double value, int precision = 0);

// Parses the whole of `text` (surrounding blanks allowed, a leading '+'
// allowed) as a double; nullopt when it is not exactly one number.
std::optional<double> ParseDouble(std::string_view text);
std::optional<long long> ParseInteger(std::string_view text);

std::string_view Trim(std::string_view text);
std::string ToUpper(std::string_view text);
bool EqualsIgnoreCase(std::string_view a, std::string_view b);

// `text` unchanged when it is valid UTF-8 (a leading BOM removed), else
// converted from ISO-8859-1 to UTF-8.
std::string ToUtf8(std::string text);

}  // namespace napkin::formats
