#include "util/output_destination.h"

#include <fcntl.h>
#include <limits.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <random>
#include <system_error>
#include <vector>

#include "common/error.h"

namespace napkin::util {

namespace {

namespace fs = std::filesystem;

struct ProtectedFile {
  fs::path path;
  std::string what;
  Refusal refusal = Refusal::kInput;
};

std::mutex& ProtectedMutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<ProtectedFile>& ProtectedFiles() {
  static std::vector<ProtectedFile> files;
  return files;
}

// Appended, not `"'" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
std::string Named(const fs::path& path) { return std::string("'").append(path.string()).append("'"); }

struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileIdentity& other) const { return device == other.device && inode == other.inode; }
};

FileIdentity IdentityOf(const struct stat& status) { return {status.st_dev, status.st_ino}; }

// A name in a folder, the folder known by its device and inode: how a file
// that does not exist yet (a catalogue's -wal) is recognised by any spelling.
struct EntryKey {
  FileIdentity folder;
  std::string name;
  bool operator==(const EntryKey& other) const { return folder == other.folder && name == other.name; }
};

// What a protected file is known by now (not when protection began: a side
// file such as the write-ahead log comes and goes while the catalogue is
// open): the file itself, and its name in its folder under the spelling given
// and with every link resolved.
void KeysOf(const fs::path& path, std::vector<FileIdentity>& files, std::vector<EntryKey>& entries) {
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0) files.push_back(IdentityOf(status));
  std::error_code error;
  fs::path resolved = fs::weakly_canonical(fs::absolute(path, error), error);
  for (const fs::path& spelling : {path, resolved}) {
    if (spelling.empty() || !spelling.has_filename()) continue;
    const fs::path parent = spelling.parent_path().empty() ? fs::path(".") : spelling.parent_path();
    if (::stat(parent.c_str(), &status) == 0) entries.push_back({IdentityOf(status), spelling.filename()});
  }
}

std::vector<ProtectedFile> ProtectedSnapshot() {
  const std::lock_guard lock(ProtectedMutex());
  return ProtectedFiles();
}

[[noreturn]] void Refuse(const std::string& shown, const ProtectedFile& file) {
  const std::string sentence =
      Named(shown) + " is " + file.what + "; napkin never writes output over it (name another file).";
  if (file.refusal == Refusal::kUsage) throw UsageError(sentence);
  throw InputError(sentence);
}

// Throws when the entry `key`, or the file `identity` (when it exists), is protected.
void CheckKeys(const std::optional<EntryKey>& key, const std::optional<FileIdentity>& identity,
               const std::string& shown) {
  for (const ProtectedFile& file : ProtectedSnapshot()) {
    std::vector<FileIdentity> files;
    std::vector<EntryKey> entries;
    KeysOf(file.path, files, entries);
    for (const FileIdentity& protected_file : files)
      if (identity && *identity == protected_file) Refuse(shown, file);
    for (const EntryKey& entry : entries)
      if (key && *key == entry) Refuse(shown, file);
  }
}

std::string RandomHex() {
  static thread_local std::mt19937_64 random(std::random_device{}());
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%016llx", static_cast<unsigned long long>(random()));
  return buffer;
}

constexpr const char* kTemporaryInfix = ".tmp-";
constexpr std::size_t kHexDigits = 16;
// NAME_MAX of Linux file systems.
constexpr std::size_t kNameMax = 255;

}  // namespace

OpenedEntry OpenEntry(const fs::path& requested) {
  if (requested.empty()) throw UsageError("an empty path names no file; name a file.");
  UniqueFd base;  // the folder the next path is relative to; none: the working folder
  fs::path path = requested;
  fs::path shown = requested;  // the path with links followed, for messages
  // As the kernel's own limit (ELOOP after 40 links).
  for (int links = 0; links <= 40; ++links) {
    const std::string name = path.filename().string();
    if (name.empty() || name == "." || name == "..")
      throw InputError(Named(requested) + " is a folder; name a file to write.");
    const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    UniqueFd folder(
        ::openat(base.valid() ? base.get() : AT_FDCWD, parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (!folder.valid()) {
      const int error = errno;
      const fs::path shown_parent = shown.parent_path().empty() ? fs::path(".") : shown.parent_path();
      if (error == ENOENT)
        throw InputError(Named(requested) + ": the folder " + Named(shown_parent) + " does not exist.");
      if (error == ENOTDIR)
        throw InputError(Named(requested) + ": " + Named(shown_parent) + " is not a folder.");
      throw InputError(Named(requested) + ": cannot open the folder " + Named(shown_parent) + " (" +
                       std::strerror(error) + ").");
    }
    struct stat status {};
    if (::fstatat(folder.get(), name.c_str(), &status, AT_SYMLINK_NOFOLLOW) != 0) {
      if (errno != ENOENT)
        throw InputError(Named(requested) + ": cannot be examined (" + std::strerror(errno) + ").");
      return {std::move(folder), name, shown, std::nullopt};
    }
    if (!S_ISLNK(status.st_mode)) return {std::move(folder), name, shown, status};
    // A link: followed once, relative to the folder that holds it.
    char target[PATH_MAX];
    const ssize_t length = ::readlinkat(folder.get(), name.c_str(), target, sizeof(target) - 1);
    if (length < 0)
      throw InputError(Named(requested) + ": cannot read the symbolic link " + Named(shown) + " (" +
                       std::strerror(errno) + ").");
    path = std::string(target, static_cast<std::size_t>(length));
    shown = path.is_absolute() ? path : shown.parent_path() / path;
    base = std::move(folder);
  }
  throw InputError(Named(requested) + ": too many levels of symbolic links.");
}

void ProtectFromOutput(const fs::path& file, const std::string& what, Refusal refusal) {
  const std::lock_guard lock(ProtectedMutex());
  ProtectedFiles().push_back({file, what, refusal});
}

void ClearOutputProtection() {
  const std::lock_guard lock(ProtectedMutex());
  ProtectedFiles().clear();
}

void CheckNotProtected(const OpenedEntry& entry, const std::string& shown) {
  struct stat folder {};
  std::optional<EntryKey> key;
  if (entry.folder.valid() && ::fstat(entry.folder.get(), &folder) == 0)
    key = EntryKey{IdentityOf(folder), entry.name};
  std::optional<FileIdentity> identity;
  if (entry.status) identity = IdentityOf(*entry.status);
  CheckKeys(key, identity, shown);
}

void CheckNotProtected(const fs::path& requested) {
  if (ProtectedSnapshot().empty()) return;
  OpenedEntry entry;
  try {
    entry = OpenEntry(requested);
  } catch (const InputError&) {
    return;  // nothing there to protect: whoever writes it gives the reason
  }
  CheckNotProtected(entry, requested.string());
}

OutputDestination ResolveOutputDestination(const fs::path& requested) {
  if (requested == kStandardOutputName) return {OutputDestination::Kind::kStandardOutput, {}, {}};
  OutputDestination destination;
  destination.entry = OpenEntry(requested);
  destination.path = destination.entry.path;
  CheckNotProtected(destination.entry, requested.string());
  if (!destination.entry.status) {
    destination.kind = OutputDestination::Kind::kFile;
    return destination;
  }
  const mode_t type = destination.entry.status->st_mode & S_IFMT;
  switch (type) {
    case S_IFREG:
      destination.kind = OutputDestination::Kind::kFile;
      return destination;
    case S_IFIFO:
    case S_IFCHR:
      destination.kind = OutputDestination::Kind::kStream;
      return destination;
    case S_IFDIR:
      throw InputError(Named(requested) + " is a folder; name a file to write.");
    case S_IFBLK:
      throw InputError(Named(requested) +
                       " is a block device; napkin writes files, FIFOs and character devices only.");
    case S_IFSOCK:
      throw InputError(Named(requested) +
                       " is a socket; napkin writes files, FIFOs and character devices only.");
    default:
      throw InputError(Named(requested) + " is no regular file, FIFO or character device.");
  }
}

void CheckDistinctOutputs(const std::initializer_list<std::pair<std::string, std::string>>& outputs) {
  struct Seen {
    std::string option;
    std::string value;
    EntryKey key;
    std::optional<FileIdentity> identity;
  };
  std::vector<Seen> seen;
  for (const auto& [option, value] : outputs) {
    if (value.empty() || value == kStandardOutputName) continue;
    OpenedEntry entry;
    try {
      entry = OpenEntry(value);
    } catch (const InputError&) {
      continue;  // refused with its own reason when written
    }
    struct stat folder {};
    if (::fstat(entry.folder.get(), &folder) != 0) continue;
    if (entry.status && !S_ISREG(entry.status->st_mode)) continue;  // a stream takes any number of writers
    Seen current{option, value, {IdentityOf(folder), entry.name}, std::nullopt};
    if (entry.status) current.identity = IdentityOf(*entry.status);
    for (const Seen& other : seen)
      if (other.key == current.key ||
          (other.identity && current.identity && *other.identity == *current.identity))
        throw UsageError(option + " '" + value + "' is the file " + other.option + " '" + other.value +
                         "' writes; each output needs a file of its own.");
    seen.push_back(std::move(current));
  }
}

std::string TemporaryNameFor(const std::string& name) {
  const std::size_t extra = 1 + std::strlen(kTemporaryInfix) + kHexDigits;
  std::size_t keep = name.size();
  if (keep + extra > kNameMax) {
    keep = kNameMax > extra ? kNameMax - extra : 0;
    // Not inside a UTF-8 sequence: back up over continuation bytes (10xxxxxx).
    while (keep > 0 && (static_cast<unsigned char>(name[keep]) & 0xC0) == 0x80) --keep;
  }
  return std::string(".").append(name, 0, keep).append(kTemporaryInfix).append(RandomHex());
}

bool IsTemporaryNameOf(const std::string& candidate, const std::string& name) {
  const std::size_t tail = std::strlen(kTemporaryInfix) + kHexDigits;
  if (candidate.size() < 1 + tail || candidate.front() != '.') return false;
  const std::string infix = candidate.substr(candidate.size() - tail, std::strlen(kTemporaryInfix));
  if (infix != kTemporaryInfix) return false;
  const std::string kept = candidate.substr(1, candidate.size() - 1 - tail);
  // The whole name, or the prefix a name too long to carry the suffix was cut to.
  if (kept == name) return true;
  return candidate.size() >= kNameMax - 3 && !kept.empty() && name.compare(0, kept.size(), kept) == 0;
}

}  // namespace napkin::util
