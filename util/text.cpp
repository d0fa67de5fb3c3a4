#include "util/text.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "common/error.h"
#include "util/utf8.h"

namespace napkin::util {

void AppendNumber(std::string& out, double value, int precision) {
  char buffer[64];
  const std::to_chars_result result = precision <= 0 ? std::to_chars(buffer, buffer + sizeof(buffer), value)
                                                     : std::to_chars(buffer, buffer + sizeof(buffer), value,
                                                                     std::chars_format::general, precision);
  out.append(buffer, result.ptr);
}

std::string FormatNumber(double value, int precision) {
  std::string out;
  AppendNumber(out, value, precision);
  return out;
}

std::string_view Trim(std::string_view text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end &&
         (text[begin] == ' ' || text[begin] == '\t' || text[begin] == '\r' || text[begin] == '\n'))
    ++begin;
  while (end > begin && (text[end - 1] == ' ' || text[end - 1] == '\t' || text[end - 1] == '\r' ||
                         text[end - 1] == '\n' || text[end - 1] == '\0'))
    --end;
  return text.substr(begin, end - begin);
}

std::optional<double> ParseDouble(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const std::from_chars_result result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec == std::errc::result_out_of_range) {
    // Underflow to a denormal/zero is still a number; overflow is not finite.
    const double fallback = std::strtod(std::string(text).c_str(), nullptr);
    return fallback;
  }
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<long long> ParseInteger(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  long long value = 0;
  const std::from_chars_result result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

std::string ToUpper(std::string_view text) {
  std::string upper(text);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return upper;
}

std::string ToLower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::toupper(static_cast<unsigned char>(a[i])) != std::toupper(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

std::string ToUtf8(std::string text) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  if (IsValidUtf8(text)) return text;
  return Latin1ToUtf8(text);
}

}  // namespace napkin::util

namespace napkin::util {
namespace {

// Length of the C1 control character (U+0080..U+009F, UTF-8 "\xC2\x80".."\xC2\x9F") at `i`, else 0.
std::size_t C1ControlAt(std::string_view text, std::size_t i) {
  if (i + 1 < text.size() && static_cast<unsigned char>(text[i]) == 0xC2) {
    const auto next = static_cast<unsigned char>(text[i + 1]);
    if (next >= 0x80 && next <= 0x9F) return 2;
  }
  return 0;
}

bool IsC0OrDelete(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u < 0x20 || u == 0x7F;
}

}  // namespace

bool HasControlCharacter(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i)
    if (IsC0OrDelete(text[i]) || C1ControlAt(text, i) > 0) return true;
  return false;
}

std::string EscapeControl(std::string_view text) {
  if (!HasControlCharacter(text) && IsValidUtf8(text)) return std::string(text);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string escaped;
  escaped.reserve(text.size() + 8);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (C1ControlAt(text, i) > 0) {
      const auto code = static_cast<unsigned char>(text[i + 1]);
      escaped += "\\u00";
      escaped += kHex[code >> 4];
      escaped += kHex[code & 0xF];
      ++i;
    } else if (c == '\n') {
      escaped += "\\n";
    } else if (c == '\r') {
      escaped += "\\r";
    } else if (c == '\t') {
      escaped += "\\t";
    } else if (IsC0OrDelete(c) || Utf8SequenceLength(text, i) == 0) {
      // A control character, or a byte of no valid UTF-8 sequence (text of
      // another encoding, a sequence cut short).
      const auto code = static_cast<unsigned char>(c);
      escaped += "\\x";
      escaped += kHex[code >> 4];
      escaped += kHex[code & 0xF];
    } else {
      const std::size_t length = Utf8SequenceLength(text, i);
      escaped.append(text.substr(i, length));
      i += length - 1;
    }
  }
  return escaped;
}

std::string Abbreviated(std::string_view text, std::size_t max_chars) {
  if (text.size() <= max_chars) return EscapeControl(text);
  std::size_t cut = max_chars;
  // Do not cut a UTF-8 sequence in two.
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return EscapeControl(text.substr(0, cut)) + "…(" + std::to_string(text.size() - cut) + " more bytes)";
}

void CheckName(std::string_view what, std::string_view name) {
  if (name.empty()) throw InputError(std::string(what) + " must not be empty.");
  CheckUtf8(what, name);
  if (name.size() > kMaxNameBytes)
    throw InputError(std::string(what) + " '" + Abbreviated(name) + "' is " + std::to_string(name.size()) +
                     " bytes long; names are limited to " + std::to_string(kMaxNameBytes) + " bytes.");
  if (HasControlCharacter(name))
    throw InputError(std::string(what) + " '" + Abbreviated(name) +
                     "' contains a control character (shown escaped); names must be printable text.");
}

std::string FileNameComponent(std::string_view name) {
  std::string safe;
  safe.reserve(name.size());
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (C1ControlAt(name, i) > 0) {
      safe += '_';
      ++i;
    } else if (IsC0OrDelete(c) || c == '/' || c == '\\' || c == ':') {
      safe += '_';
    } else {
      safe += c;
    }
  }
  if (safe.empty() || safe.front() == '.') safe.insert(safe.begin(), '_');
  return safe;
}

}  // namespace napkin::util
