#include "ingest/zip_input.h"

#include <errno.h>
#include <fcntl.h>
#include <unistd.h>

#include <map>
#include <system_error>
#include <vector>

#include "common/error.h"
#include "ingest/input_formats.h"
#include "ingest/temporary_folder.h"
#include "util/text.h"

namespace napkin::ingest {
namespace fs = std::filesystem;

namespace {

// Members a test is made of, as the input-format table says (InputFormatEntry::is_part: .mme,
// .chn, .csv, three-digit extensions). Others (reports, photographs) are not read.
bool IsTestMember(const formats::ZipMember& member) {
  if (member.directory) return false;
  const fs::path name(member.name);
  if (name.filename().string().front() == '.') return false;
  return IsTestPart(name);
}

// `member` as docs/formats.md names it in messages: "ARCHIVE.zip:MEMBER".
std::string MemberInArchive(const fs::path& archive, const std::string& member) {
  return archive.string() + ":" + util::Abbreviated(member, util::kQuotedInputLongChars);
}

// Writes one member's bytes; throws InputError naming the member when the
// file system refuses (a name too long for it, a file where a folder should be).
void WriteMember(const fs::path& path, const std::string& bytes, const std::string& shown) {
  const auto refuse = [&](int error) {
    throw InputError(shown + " cannot be unpacked (" + std::generic_category().message(error) + ").");
  };
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  if (error) refuse(error.value());
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) refuse(errno);
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int saved = n < 0 ? errno : EIO;
      close(fd);
      refuse(saved);
    }
    written += static_cast<std::size_t>(n);
  }
  if (close(fd) != 0) refuse(errno);
}

}  // namespace

ArchiveTest::ArchiveTest(const fs::path& archive, const formats::ZipLimits& limits) : archive_(archive) {
  formats::ZipArchive zip(archive, limits);  // checks every member name before anything is read
  // Where each test member goes, every clash found before anything is written.
  std::map<std::string, const formats::ZipMember*> targets;  // relative path -> member
  for (const formats::ZipMember& member : zip.members()) {
    if (!IsTestMember(member)) continue;
    const std::string relative = fs::path(member.name).lexically_normal().generic_string();
    if (relative.empty() || relative == "." || relative == ".." || relative.starts_with("../"))
      throw InputError(MemberInArchive(archive, member.name) + " leaves the archive.");  // UnsafeMemberName
    if (!targets.emplace(relative, &member).second)
      throw InputError(MemberInArchive(archive, member.name) + " is in the archive twice.");
  }
  for (const auto& [relative, member] : targets) {
    const auto inside = targets.lower_bound(relative + "/");
    if (inside != targets.end() && inside->first.starts_with(relative + "/"))
      throw InputError(MemberInArchive(archive, inside->second->name) + " cannot be unpacked: \"" +
                       util::Abbreviated(member->name, util::kQuotedInputLongChars) +
                       "\" is a file of the archive, not a folder.");
  }
  if (targets.empty())
    throw InputError(archive.string() + ": the zip archive holds no test (" + NoTestOfAnyFormat(false) +
                     ").");

  folder_ = std::make_unique<TemporaryFolder>("napkin-zip-", archive.string());
  std::vector<std::string> files;
  files.reserve(targets.size());
  for (const auto& target : targets) files.push_back(target.first);
  folder_->Plan(files);  // a signal from here on removes what was written
  for (const auto& [relative, member] : targets)
    WriteMember(folder_->path() / relative, zip.Read(*member), MemberInArchive(archive, member->name));

  const Discovery inside = DiscoverInputs({folder_->path().string()});
  if (inside.inputs.size() != 1 || !inside.errors.empty())
    throw InputError(archive.string() + ": the zip archive holds " + std::to_string(inside.inputs.size()) +
                     " tests; napkin imports one test per archive.");
  input_ = inside.inputs.front();
}

ArchiveTest::~ArchiveTest() = default;  // the TemporaryFolder removes itself

std::string ArchiveTest::InArchiveTerms(const std::string& message) const {
  const std::string root = folder_->path().string() + "/";
  const std::string replacement = archive_.string() + ":";
  std::string out;
  std::size_t position = 0;
  for (std::size_t found; (found = message.find(root, position)) != std::string::npos;
       position = found + root.size())
    out.append(message, position, found - position).append(replacement);
  out.append(message, position, std::string::npos);
  // The temporary folder itself (e.g. a test folder at the archive's top).
  const std::string bare = folder_->path().string();
  for (std::size_t found; (found = out.find(bare)) != std::string::npos;)
    out.replace(found, bare.size(), archive_.string());
  return out;
}

}  // namespace napkin::ingest
