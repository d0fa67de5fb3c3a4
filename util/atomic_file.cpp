#include "util/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <memory>
#include <random>
#include <system_error>
#include <vector>

#include "common/error.h"

namespace napkin::util {
namespace {

namespace fs = std::filesystem;

// Appended, not `"'" + temporary` (GCC 12's false -Wrestrict, util/text.h InQuotes).
std::string QuotedPath(const fs::path& path) { return std::string("'").append(path.string()).append("'"); }

std::string ErrnoText(int error) { return std::strerror(error); }

// What kind of file `mode` is, for a sentence.
std::string KindOf(mode_t mode) {
  switch (mode & S_IFMT) {
    case S_IFDIR:
      return "a folder";
    case S_IFLNK:
      return "a symbolic link";
    case S_IFIFO:
      return "a FIFO";
    case S_IFCHR:
      return "a character device";
    case S_IFBLK:
      return "a block device";
    case S_IFSOCK:
      return "a socket";
    default:
      return "a regular file";
  }
}

[[noreturn]] void ChangedMeanwhile(const fs::path& destination, const std::string& now) {
  throw InputError(QuotedPath(destination) + " changed while napkin was writing it (it is now " + now +
                   "); nothing was written over it (try again).");
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(std::move(destination)), target_(ResolveOutputDestination(destination_)) {
  const int folder = target_.entry.folder.get();
  const char* name = target_.entry.name.c_str();
  int descriptor = -1;
  switch (target_.kind) {
    case OutputDestination::Kind::kStandardOutput:
      file_ = stdout;
      return;
    case OutputDestination::Kind::kStream: {
      // A FIFO or device: opened as it is (a FIFO waits for its reader here),
      // never through a link swapped in since it was examined, and checked to
      // be the very node examined: O_WRONLY without O_CREAT or O_TRUNC leaves
      // any other file untouched.
      descriptor = ::openat(folder, name, O_WRONLY | O_NOFOLLOW | O_NOCTTY | O_CLOEXEC);
      if (descriptor < 0) {
        if (errno == ELOOP) ChangedMeanwhile(destination_, "a symbolic link");
        throw InputError(destination_.string() + ": cannot open the output (" + ErrnoText(errno) + ").");
      }
      struct stat opened {};
      if (::fstat(descriptor, &opened) != 0 || opened.st_dev != target_.entry.status->st_dev ||
          opened.st_ino != target_.entry.status->st_ino) {
        ::close(descriptor);
        ChangedMeanwhile(destination_, "another file");
      }
      break;
    }
    case OutputDestination::Kind::kFile: {
      temporary_ = TemporaryNameFor(target_.entry.name);
      const bool replacing = target_.entry.status.has_value();
      descriptor =
          ::openat(folder, temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
      if (descriptor < 0) {
        const int error = errno;
        temporary_.clear();
        const fs::path where =
            target_.path.parent_path().empty() ? fs::path(".") : target_.path.parent_path();
        throw InputError(destination_.string() + ": cannot create the output file in the folder " +
                         QuotedPath(where) + " (" + ErrnoText(error) + ").");
      }
      if (replacing) {
        // The replaced file's owner, group and mode (a private file stays
        // private). The owner can be given away by root only; the group by
        // its members: each is kept where the process may, else it is the
        // process's own, as for a new file.
        const struct stat& old = *target_.entry.status;
        if (::fchown(descriptor, old.st_uid, old.st_gid) != 0) (void)!::fchown(descriptor, -1, old.st_gid);
        (void)!::fchmod(descriptor, old.st_mode & 07777);
      }
      break;
    }
  }
  file_ = ::fdopen(descriptor, "wb");
  if (file_ == nullptr) {
    const int error = errno;
    ::close(descriptor);
    throw InputError(destination_.string() + ": cannot open the output (" + ErrnoText(error) + ").");
  }
  // A large buffer: writers emit many short numbers.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) ::unlinkat(target_.entry.folder.get(), temporary_.c_str(), 0);
}

void AtomicFile::Write(std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    throw InputError(destination_.string() + ": write failed (" + ErrnoText(errno) + ").");
}

void AtomicFile::Printf(const char* format, ...) {
  va_list args;
  va_start(args, format);
  const int written = std::vfprintf(file_, format, args);
  va_end(args);
  if (written < 0) throw InputError(destination_.string() + ": write failed (" + ErrnoText(errno) + ").");
}

void AtomicFile::Commit() {
  if (target_.kind != OutputDestination::Kind::kFile) {
    // Nothing to rename: the bytes went straight to the stream.
    const bool flushed = std::fflush(file_) == 0;
    const bool closed = file_ == stdout || std::fclose(file_) == 0;
    file_ = nullptr;
    if (!flushed || !closed)
      throw InputError(destination_.string() + ": write failed (" + ErrnoText(errno) + ").");
    committed_ = true;
    return;
  }
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed)
    throw InputError(destination_.string() + ": write failed (" + ErrnoText(errno) + ").");
  // What the name is now, in the folder opened at the start: it may have
  // been replaced since (another process). A regular file, or nothing, is
  // replaced unless it is protected; anything else is left as it is.
  OpenedEntry& entry = target_.entry;
  struct stat now {};
  if (::fstatat(entry.folder.get(), entry.name.c_str(), &now, AT_SYMLINK_NOFOLLOW) == 0) {
    if (!S_ISREG(now.st_mode)) ChangedMeanwhile(destination_, KindOf(now.st_mode));
    entry.status = now;
  } else {
    entry.status.reset();
  }
  CheckNotProtected(entry, destination_.string());
  // renameat replaces the name in this folder, never what a link swapped in
  // after the check would point to.
  if (::renameat(entry.folder.get(), temporary_.c_str(), entry.folder.get(), entry.name.c_str()) != 0)
    throw InputError(destination_.string() + ": cannot move the output file into place (" + ErrnoText(errno) +
                     ").");
  committed_ = true;
}

void WriteFileAtomically(const std::filesystem::path& destination,
                         const std::function<void(AtomicFile&)>& write) {
  AtomicFile file(destination);
  write(file);
  file.Commit();
}

namespace {

std::atomic<int> failing_move{-1};

// The names in the folder `folder` (without "." and ".."), sorted.
std::vector<std::string> ListFolder(int folder) {
  std::vector<std::string> names;
  const int copy = ::dup(folder);
  if (copy < 0) return names;
  DIR* directory = ::fdopendir(copy);
  if (directory == nullptr) {
    ::close(copy);
    return names;
  }
  ::rewinddir(directory);
  while (const dirent* entry = ::readdir(directory)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  ::closedir(directory);
  std::sort(names.begin(), names.end());
  return names;
}

// Removes `name` in `folder` and, for a folder, all it holds, through
// descriptors (never following a link). Best effort: for cleaning up napkin's
// own staging folder.
void RemoveTree(int folder, const std::string& name) {
  if (::unlinkat(folder, name.c_str(), 0) == 0 || errno == ENOENT) return;
  const UniqueFd inner(::openat(folder, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (!inner.valid()) return;
  for (const std::string& entry : ListFolder(inner.get())) RemoveTree(inner.get(), entry);
  ::unlinkat(folder, name.c_str(), AT_REMOVEDIR);
}

// One staged file or folder and where it goes.
struct Move {
  std::shared_ptr<UniqueFd> from;  // the staging folder holding it
  std::shared_ptr<UniqueFd> to;    // the destination folder it goes into
  std::string name;
  fs::path shown;         // its destination path, for messages
  bool replaces = false;  // a regular file of that name is there (replace_existing)
  std::string backup;     // the replaced file's name in the staging root while the moves run
  bool moved = false;
};

Move MoveOf(const std::shared_ptr<UniqueFd>& from, const std::shared_ptr<UniqueFd>& to,
            const std::string& name, const fs::path& shown) {
  Move move;
  move.from = from;
  move.to = to;
  move.name = name;
  move.shown = shown;
  return move;
}

struct Plan {
  std::vector<Move> moves;
  dev_t device = 0;  // the staging folder's file system
};

// Plans the moves of the staging folder `from` into `to` (shown as `shown`),
// refusing, before anything moves, a name that would replace what the folder
// holds (a folder where a file goes or the reverse always; a file unless
// `replace_existing`; a protected file) and a subfolder on another file system.
void PlanMoves(const std::shared_ptr<UniqueFd>& from, const std::shared_ptr<UniqueFd>& to,
               const fs::path& shown, bool replace_existing, Plan& plan) {
  for (const std::string& name : ListFolder(from->get())) {
    struct stat staged {};
    if (::fstatat(from->get(), name.c_str(), &staged, AT_SYMLINK_NOFOLLOW) != 0) continue;
    const fs::path target = shown / name;
    struct stat existing {};
    const bool exists = ::fstatat(to->get(), name.c_str(), &existing, AT_SYMLINK_NOFOLLOW) == 0;
    if (S_ISDIR(staged.st_mode)) {
      if (!exists) {
        plan.moves.push_back(MoveOf(from, to, name, target));
        continue;
      }
      // An existing folder, or a link to one: followed once, then used by descriptor.
      auto inner =
          std::make_shared<UniqueFd>(::openat(to->get(), name.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
      if (!inner->valid())
        throw InputError(QuotedPath(target) + " exists and is not a folder; napkin does not replace it.");
      struct stat opened {};
      if (::fstat(inner->get(), &opened) != 0 || opened.st_dev != plan.device)
        throw InputError(QuotedPath(target) +
                         " is on another file system than the export's folder (a link to elsewhere?): napkin "
                         "moves an export's files into place by renaming them, which cannot cross file "
                         "systems; nothing was exported (export into a folder on that file system).");
      auto staged_inner = std::make_shared<UniqueFd>(
          ::openat(from->get(), name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
      if (!staged_inner->valid())
        throw InputError(QuotedPath(target) + ": cannot open the staged folder (" + ErrnoText(errno) + ").");
      PlanMoves(staged_inner, inner, target, replace_existing, plan);
      continue;
    }
    OpenedEntry entry;
    entry.folder = UniqueFd(::dup(to->get()));
    entry.name = name;
    if (exists) entry.status = existing;
    CheckNotProtected(entry, target.string());
    if (exists) {
      if (!S_ISREG(existing.st_mode))
        throw InputError(QuotedPath(target) +
                         " exists and is not a regular file; napkin does not replace it.");
      if (!replace_existing)
        throw InputError(QuotedPath(target) +
                         " already exists; napkin does not replace it unless --force is given.");
    }
    Move move = MoveOf(from, to, name, target);
    move.replaces = exists;
    plan.moves.push_back(std::move(move));
  }
}

// Moves every planned file into place; on a failure takes back what moved
// (restoring each file it replaced) and throws.
void RunMoves(Plan& plan, int staging_root) {
  auto undo = [&] {
    for (auto move = plan.moves.rbegin(); move != plan.moves.rend(); ++move) {
      if (move->moved) {
        // Ours goes back to the staging folder; the replaced file comes back.
        ::renameat(move->to->get(), move->name.c_str(), move->from->get(), move->name.c_str());
        move->moved = false;
      }
      if (!move->backup.empty())
        ::renameat(staging_root, move->backup.c_str(), move->to->get(), move->name.c_str());
    }
  };
  for (std::size_t i = 0; i < plan.moves.size(); ++i) {
    Move& move = plan.moves[i];
    int error = 0;
    if (move.replaces) {
      // A second name for the replaced file, to restore it should a later move
      // fail. Where a hard link is not allowed, the file itself is moved aside.
      const std::string backup = ".backup-" + std::to_string(i);
      if (::linkat(move.to->get(), move.name.c_str(), staging_root, backup.c_str(), 0) == 0 ||
          ::renameat(move.to->get(), move.name.c_str(), staging_root, backup.c_str()) == 0)
        move.backup = backup;
      else
        error = errno;
    }
    if (error == 0 && static_cast<int>(i) == failing_move.load()) error = EIO;
    if (error == 0 && ::renameat(move.from->get(), move.name.c_str(), move.to->get(), move.name.c_str()) != 0)
      error = errno;
    if (error != 0) {
      undo();
      failing_move = -1;
      throw InputError(move.shown.string() + ": cannot move the output file into place (" + ErrnoText(error) +
                       "); nothing was exported.");
    }
    move.moved = true;
  }
  failing_move = -1;
}

// `message` with the staging folder's name replaced by the destination's:
// the user named the destination, the staging folder is napkin's own.
std::string NamingDestination(std::string message, const std::string& staging, const fs::path& destination) {
  const std::string to = destination.string();
  for (std::size_t at = message.find(staging); at != std::string::npos;
       at = message.find(staging, at + to.size()))
    message.replace(at, staging.size(), to);
  return message;
}

// The destination folder without a trailing separator ("iso/" is "iso").
fs::path WithoutTrailingSeparator(const fs::path& destination) {
  fs::path folder = destination;
  while (!folder.has_filename() && folder.has_parent_path() && folder != folder.root_path())
    folder = folder.parent_path();
  return folder;
}

}  // namespace

void FailFolderMoveForTesting(int move_index) { failing_move = move_index; }

void WriteDirectoryAtomically(const fs::path& destination,
                              const std::function<void(const fs::path& directory)>& fill,
                              bool replace_existing) {
  if (destination.empty()) throw UsageError("an empty path names no folder; name a folder.");
  const fs::path folder_path = WithoutTrailingSeparator(destination);
  // The folder holding the destination (made when missing; napkin's own
  // folders then), and the destination opened once: every later step works
  // on these descriptors.
  auto destination_folder = std::make_shared<UniqueFd>();
  UniqueFd parent;
  std::string name;
  bool created = false;
  const std::string last = folder_path.filename().string();
  if (last.empty() || last == "." || last == "..") {
    *destination_folder = UniqueFd(::open(folder_path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  } else {
    std::error_code error;
    if (folder_path.has_parent_path()) fs::create_directories(folder_path.parent_path(), error);
    OpenedEntry entry = OpenEntry(folder_path);
    if (!entry.status) {
      if (::mkdirat(entry.folder.get(), entry.name.c_str(), 0777) == 0)
        created = true;
      else if (errno != EEXIST)
        throw InputError(destination.string() + ": cannot create the output folder (" + ErrnoText(errno) +
                         ").");
    }
    *destination_folder = UniqueFd(
        ::openat(entry.folder.get(), entry.name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
    parent = std::move(entry.folder);
    name = entry.name;
  }
  if (!destination_folder->valid()) {
    if (errno == ENOTDIR || errno == ELOOP)
      throw InputError(destination.string() + ": exists and is not a folder.");
    throw InputError(destination.string() + ": cannot open the output folder (" + ErrnoText(errno) + ").");
  }
  // Inside the destination: the same file system, so every move is a rename,
  // and no other folder needs to be writable.
  const std::string staging_name = ".napkin-staging-" + TemporaryNameFor("x").substr(7);
  auto remove_created = [&] {
    if (created)
      ::unlinkat(parent.get(), name.c_str(), AT_REMOVEDIR);  // only when empty: nothing else was there
  };
  if (::mkdirat(destination_folder->get(), staging_name.c_str(), 0700) != 0) {
    const int error = errno;
    remove_created();
    throw InputError(destination.string() + ": cannot create the output folder's staging folder (" +
                     ErrnoText(error) + ").");
  }
  auto staging = std::make_shared<UniqueFd>(::openat(destination_folder->get(), staging_name.c_str(),
                                                     O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  // `fill` writes by path: a path through /proc/self/fd reaches the staging
  // folder opened here, whatever is renamed or swapped along `destination`.
  const std::string through_descriptor = "/proc/self/fd/" + std::to_string(staging->get());
  struct stat proc {};
  const std::string staging_path =
      staging->valid() && ::stat(through_descriptor.c_str(), &proc) == 0 && S_ISDIR(proc.st_mode)
          ? through_descriptor
          : (folder_path / staging_name).string();
  try {
    if (!staging->valid())
      throw InputError(destination.string() + ": cannot open the staging folder (" + ErrnoText(errno) + ").");
    fill(staging_path);
    Plan plan;
    struct stat staged {};
    if (::fstat(staging->get(), &staged) != 0)
      throw InputError(destination.string() + ": cannot examine the staging folder (" + ErrnoText(errno) +
                       ").");
    plan.device = staged.st_dev;
    PlanMoves(staging, destination_folder, folder_path, replace_existing, plan);
    RunMoves(plan, staging->get());
    // The replaced files' second names and staging's own, now empty, folders.
    RemoveTree(destination_folder->get(), staging_name);
  } catch (...) {
    RemoveTree(destination_folder->get(), staging_name);
    remove_created();
    try {
      throw;
    } catch (const UsageError& usage) {
      throw UsageError(NamingDestination(usage.what(), staging_path, folder_path));
    } catch (const InputError& input) {
      throw InputError(NamingDestination(input.what(), staging_path, folder_path));
    } catch (const std::filesystem::filesystem_error& error) {
      // A writer's file system call: a sentence naming the path, not a bug.
      throw InputError(NamingDestination(error.path1().string(), staging_path, folder_path) + ": " +
                       error.code().message() + ".");
    }
  }
}

}  // namespace napkin::util
