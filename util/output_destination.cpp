#include "util/output_destination.h"

#include <sys/stat.h>

#include <mutex>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "common/error.h"

namespace napkin::util {
namespace {

namespace fs = std::filesystem;

struct ProtectedFile {
  fs::path path;
  std::string what;
};

std::mutex& ProtectedMutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<ProtectedFile>& ProtectedFiles() {
  static std::vector<ProtectedFile> files;
  return files;
}

std::string Named(const fs::path& path) { return "'" + path.string() + "'"; }

// `path` with every symbolic link of its last component followed (the link
// may name a file that does not exist yet). Folders along the way are left
// to the kernel.
fs::path FollowLinks(const fs::path& requested) {
  fs::path path = requested;
  // As the kernel's own limit (ELOOP after 40 links).
  for (int links = 0; links < 40; ++links) {
    std::error_code error;
    if (!fs::is_symlink(fs::symlink_status(path, error))) return path;
    const fs::path target = fs::read_symlink(path, error);
    if (error)
      throw InputError(Named(requested) + ": cannot read the symbolic link " + Named(path) + " (" +
                       error.message() + ").");
    path = target.is_absolute() ? target : path.parent_path() / target;
  }
  throw InputError(Named(requested) + ": too many levels of symbolic links.");
}

struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
};

std::optional<FileIdentity> IdentityOf(const fs::path& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return std::nullopt;
  return FileIdentity{status.st_dev, status.st_ino};
}

// The absolute path with ".", ".." and the symbolic links of its existing
// part resolved, to compare names of files that do not exist yet.
fs::path ComparablePath(const fs::path& path) {
  std::error_code error;
  fs::path resolved = fs::weakly_canonical(fs::absolute(FollowLinks(path)), error);
  return error ? fs::absolute(path).lexically_normal() : resolved;
}

}  // namespace

void ProtectFromOutput(const fs::path& file, const std::string& what) {
  const std::lock_guard lock(ProtectedMutex());
  ProtectedFiles().push_back({file, what});
}

void ClearOutputProtection() {
  const std::lock_guard lock(ProtectedMutex());
  ProtectedFiles().clear();
}

void CheckNotProtected(const fs::path& requested) {
  std::vector<ProtectedFile> files;
  {
    const std::lock_guard lock(ProtectedMutex());
    files = ProtectedFiles();
  }
  if (files.empty()) return;
  // Identities are taken now, not when protection began: a side file (the
  // write-ahead log) comes and goes while the catalogue is open.
  const std::optional<FileIdentity> identity = IdentityOf(requested);
  const fs::path comparable = ComparablePath(requested);
  for (const ProtectedFile& file : files) {
    bool same = false;
    if (identity) {
      const std::optional<FileIdentity> other = IdentityOf(file.path);
      same = other && other->device == identity->device && other->inode == identity->inode;
    }
    same = same || ComparablePath(file.path) == comparable;
    if (same)
      throw InputError(Named(requested) + " is " + file.what + "; napkin never writes output over it (name " +
                       "another file).");
  }
}

OutputDestination ResolveOutputDestination(const fs::path& requested) {
  if (requested == kStandardOutputName) return {OutputDestination::Kind::kStandardOutput, {}};
  CheckNotProtected(requested);
  OutputDestination destination;
  destination.path = FollowLinks(requested);
  std::error_code error;
  const fs::file_status status = fs::status(destination.path, error);
  switch (status.type()) {
    case fs::file_type::not_found:
    case fs::file_type::regular:
      destination.kind = OutputDestination::Kind::kFile;
      return destination;
    case fs::file_type::fifo:
    case fs::file_type::character:
      destination.kind = OutputDestination::Kind::kStream;
      return destination;
    case fs::file_type::directory:
      throw InputError(Named(requested) + " is a folder; name a file to write.");
    case fs::file_type::block:
      throw InputError(Named(requested) +
                       " is a block device; napkin writes files, FIFOs and character devices only.");
    case fs::file_type::socket:
      throw InputError(Named(requested) +
                       " is a socket; napkin writes files, FIFOs and character devices only.");
    default:
      if (error) throw InputError(Named(requested) + ": cannot be examined (" + error.message() + ").");
      throw InputError(Named(requested) + " is no regular file, FIFO or character device.");
  }
}

}  // namespace napkin::util
