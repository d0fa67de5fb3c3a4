#include "formats/json_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "common/error.h"

namespace napkin::formats {

std::string ReadWholeFile(const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr)
    throw InputError(path.string() + ": cannot open the file (" + std::strerror(errno) + ").");
  std::string content;
  char buffer[1 << 16];
  std::size_t count = 0;
  while ((count = std::fread(buffer, 1, sizeof(buffer), file)) > 0) content.append(buffer, count);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed) throw InputError(path.string() + ": read error.");
  return content;
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  const std::string text = ReadWholeFile(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& error) {
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string what = error.what();
    const std::size_t start = what.find("parse error");
    if (start != std::string::npos) what = what.substr(start);
    if (!what.empty() && what.back() != '.') what += '.';
    throw InputError(path.string() + ": not valid JSON (" + what.substr(0, what.size() - 1) + ").");
  }
}

}  // namespace napkin::formats
