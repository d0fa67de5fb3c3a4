#pragma once
// UTF-8 as the catalogue and every JSON answer need it (docs/formats.md
// "Names, limits and escaping", Text encoding): strict validation (RFC 3629),
// ISO-8859-1 conversion for text whose encoding is known to be one of the
// two, and the one-sentence refusal of names whose encoding is unknown.
#include <cstddef>
#include <string>
#include <string_view>

namespace napkin::util {

// Length (1 to 4) of the valid UTF-8 sequence that starts at byte `i` of
// `text` (i < text.size()), or 0 when the bytes there are not one: RFC 3629
// with the second-byte ranges of the Unicode standard's table 3-7 (no
// overlong forms, no UTF-16 surrogates, nothing above U+10FFFF).
std::size_t Utf8SequenceLength(std::string_view text, std::size_t i);

// Whether all of `text` is such sequences: what nlohmann::json's dump
// accepts, and what napkin stores.
bool IsValidUtf8(std::string_view text);

// `text` read as ISO-8859-1 (each byte one code point), written in UTF-8.
std::string Latin1ToUtf8(std::string_view text);

// Throws InputError "<what> '<text>' is not valid UTF-8 ..." (the text
// escaped: util::Abbreviated) unless IsValidUtf8(text). For text of an
// unknown encoding (file names, command-line names): refused, never guessed.
void CheckUtf8(std::string_view what, std::string_view text);

}  // namespace napkin::util
