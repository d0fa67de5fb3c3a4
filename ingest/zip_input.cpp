#include "ingest/zip_input.h"

#include <stdlib.h>

#include <fstream>
#include <system_error>

#include "common/error.h"
#include "formats/text.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

// Members a test is made of: ISO-MME (.mme, .chn, .001 ...), UDS-1992
// (.001 ...) and CSV files. Others (reports, photographs) are not read.
bool IsTestMember(const formats::ZipMember& member) {
  if (member.directory) return false;
  const fs::path name(member.name);
  if (name.filename().string().front() == '.') return false;
  const std::string extension = name.extension().string();
  if (formats::EqualsIgnoreCase(extension, ".mme") || formats::EqualsIgnoreCase(extension, ".chn") ||
      formats::EqualsIgnoreCase(extension, ".csv"))
    return true;
  return extension.size() == 4 && extension.find_first_not_of("0123456789", 1) == std::string::npos;
}

void WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw InputError("cannot write the temporary file '" + path.string() + "'.");
}

}  // namespace

ArchiveTest::ArchiveTest(const fs::path& archive, const formats::ZipLimits& limits) : archive_(archive) {
  formats::ZipArchive zip(archive, limits);  // checks every member name before anything is read
  std::string pattern = (fs::temp_directory_path() / "napkin-zip-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError(archive.string() + ": cannot create a temporary folder to read the archive in.");
  root_ = pattern;
  try {
    std::size_t extracted = 0;
    for (const formats::ZipMember& member : zip.members()) {
      if (!IsTestMember(member)) continue;
      const fs::path target = (root_ / member.name).lexically_normal();
      const fs::path relative = target.lexically_relative(root_);
      if (relative.empty() || *relative.begin() == "..")  // UnsafeMemberName already refused these
        throw InputError(archive.string() + ": member \"" + member.name + "\" leaves the archive.");
      if (fs::exists(target))
        throw InputError(archive.string() + ": member \"" + member.name + "\" is in the archive twice.");
      const std::string bytes = zip.Read(member);
      fs::create_directories(target.parent_path());
      WriteBytes(target, bytes);
      ++extracted;
    }
    if (extracted == 0)
      throw InputError(archive.string() +
                       ": the zip archive holds no test (no ISO-MME, UDS-1992 or CSV member).");
    const Discovery inside = DiscoverInputs({root_.string()});
    if (inside.inputs.size() != 1 || !inside.errors.empty())
      throw InputError(archive.string() + ": the zip archive holds " + std::to_string(inside.inputs.size()) +
                       " tests; napkin imports one test per archive.");
    input_ = inside.inputs.front();
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
    throw;
  }
}

ArchiveTest::~ArchiveTest() {
  std::error_code ignored;
  fs::remove_all(root_, ignored);
}

std::string ArchiveTest::InArchiveTerms(const std::string& message) const {
  const std::string root = root_.string() + "/";
  const std::string replacement = archive_.string() + ":";
  std::string out;
  std::size_t position = 0;
  for (std::size_t found; (found = message.find(root, position)) != std::string::npos;
       position = found + root.size())
    out.append(message, position, found - position).append(replacement);
  out.append(message, position, std::string::npos);
  // The temporary folder itself (e.g. a test folder at the archive's top).
  const std::string bare = root_.string();
  for (std::size_t found; (found = out.find(bare)) != std::string::npos;)
    out.replace(found, bare.size(), archive_.string());
  return out;
}

}  // namespace napkin::ingest
