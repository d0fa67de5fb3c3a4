#pragma once
// Small text helpers shared by the readers and writers: exact number
// formatting (std::to_chars), strict number parsing (std::from_chars),
// trimming, case-insensitive comparison, ISO-8859-1 -> UTF-8, and the one
// escaping of text that reaches a terminal, a table or a file name
// (docs/formats.md "Names, limits and escaping").
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace napkin::util {

// Appends `value`: precision 0 = shortest text that reads back to the same
// double (exact round trip); otherwise like printf("%.<precision>g").
void AppendNumber(std::string& out, double value, int precision = 0);
std::string FormatNumber(double value, int precision = 0);

// Parses the whole of `text` (surrounding blanks allowed, a leading '+'
// allowed) as a double; nullopt when it is not exactly one number.
std::optional<double> ParseDouble(std::string_view text);
std::optional<long long> ParseInteger(std::string_view text);

std::string_view Trim(std::string_view text);
// ASCII case mapping (napkin never sets a locale: std::toupper/tolower of the "C" locale).
std::string ToUpper(std::string_view text);
std::string ToLower(std::string_view text);
bool EqualsIgnoreCase(std::string_view a, std::string_view b);

// `text` unchanged when it is valid UTF-8 (util/utf8.h; a leading BOM
// removed), else converted from ISO-8859-1 to UTF-8: for text whose encoding
// is known to be one of the two (ISO-MME files, UDS-1992 header fields).
std::string ToUtf8(std::string text);

// `text` with every control character (C0, DEL, and the C1 range U+0080 to
// U+009F) written as a visible escape: \n, \r, \t, \\xHH (\\u00HH for
// C1); a backslash stays a backslash; a byte that is not part of valid
// UTF-8 is written \\xHH too, so the result is UTF-8. Everything napkin prints to a
// terminal, a table or a CSV cell goes through it, so input can never send
// terminal escape sequences.
std::string EscapeControl(std::string_view text);
bool HasControlCharacter(std::string_view text);

// `text` escaped (EscapeControl) and cut to at most `max_chars` bytes plus
// "…" (and the number of bytes left out), for quoting input in messages.
inline constexpr std::size_t kQuotedInputChars = 60;       // a cell, a value
inline constexpr std::size_t kQuotedInputLongChars = 200;  // a header field, a path
std::string Abbreviated(std::string_view text, std::size_t max_chars = kQuotedInputChars);
// The same in double quotes: a cell or value (Quoted), a header field or path (QuotedLong).
// Appended, never `"\"" + temporary`: GCC 12 warns falsely (-Wrestrict, GCC
// bug 105329) on a literal prepended to a temporary string once inlined.
inline std::string InQuotes(std::string_view text) {
  std::string quoted = "\"";
  quoted.append(text);
  quoted += '"';
  return quoted;
}
inline std::string Quoted(std::string_view text) { return InQuotes(Abbreviated(text)); }
inline std::string QuotedLong(std::string_view text) {
  return InQuotes(Abbreviated(text, kQuotedInputLongChars));
}

// Longest name napkin accepts for a test id, series, variant, array, slot,
// channel map or processing config (bytes of UTF-8).
inline constexpr std::size_t kMaxNameBytes = 256;

// Throws InputError "<what> '<name>' ..." when `name` is empty, longer than
// kMaxNameBytes, not valid UTF-8 (util::CheckUtf8) or holds a control
// character (a newline included).
void CheckName(std::string_view what, std::string_view name);

// `name` as one safe file-name component: '/', '\\', ':' and control
// characters become '_', a name starting with '.' gets a leading '_' (so
// ".", ".." and hidden names cannot arise), an empty name becomes "_".
std::string FileNameComponent(std::string_view name);

}  // namespace napkin::util
