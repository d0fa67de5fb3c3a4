#pragma once
// Reading JSON files with one-sentence errors naming the file.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace napkin::formats {

// Parses `path` as JSON. Throws InputError "<path>: ..." when it cannot be
// read or is not valid JSON (with the parser's line/column).
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

// Reads a whole file into memory. Throws InputError naming the file.
std::string ReadWholeFile(const std::filesystem::path& path);

}  // namespace napkin::formats
