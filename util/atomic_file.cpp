#include "util/atomic_file.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <random>
#include <system_error>
#include <vector>

#include "common/error.h"

namespace napkin::util {
namespace {

std::string RandomSuffix() {
  static thread_local std::mt19937_64 random(std::random_device{}());
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%016llx", static_cast<unsigned long long>(random()));
  return buffer;
}

std::filesystem::path TemporarySibling(const std::filesystem::path& destination) {
  std::filesystem::path parent = destination.parent_path();
  if (parent.empty()) parent = ".";
  return parent / ("." + destination.filename().string() + ".tmp-" + RandomSuffix());
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(std::move(destination)), target_(ResolveOutputDestination(destination_)) {
  switch (target_.kind) {
    case OutputDestination::Kind::kStandardOutput:
      file_ = stdout;
      return;
    case OutputDestination::Kind::kStream:
      // A FIFO or device: opened as it is (a FIFO waits for its reader here).
      file_ = std::fopen(target_.path.c_str(), "wb");
      break;
    case OutputDestination::Kind::kFile:
      temporary_ = TemporarySibling(target_.path);
      file_ = std::fopen(temporary_.c_str(), "wb");
      break;
  }
  if (file_ == nullptr)
    throw InputError(destination_.string() + ": cannot create the output file (" + std::strerror(errno) +
                     ").");
  // A large buffer: writers emit many short numbers.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) {
    std::error_code error;
    std::filesystem::remove(temporary_, error);
  }
}

void AtomicFile::Write(std::string_view text) {
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    throw InputError(destination_.string() + ": write failed (" + std::strerror(errno) + ").");
}

void AtomicFile::Printf(const char* format, ...) {
  va_list args;
  va_start(args, format);
  const int written = std::vfprintf(file_, format, args);
  va_end(args);
  if (written < 0) throw InputError(destination_.string() + ": write failed (" + std::strerror(errno) + ").");
}

void AtomicFile::Commit() {
  if (target_.kind != OutputDestination::Kind::kFile) {
    // Nothing to rename: the bytes went straight to the stream.
    const bool flushed = std::fflush(file_) == 0;
    const bool closed = file_ == stdout || std::fclose(file_) == 0;
    file_ = nullptr;
    if (!flushed || !closed)
      throw InputError(destination_.string() + ": write failed (" + std::strerror(errno) + ").");
    committed_ = true;
    return;
  }
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed)
    throw InputError(destination_.string() + ": write failed (" + std::strerror(errno) + ").");
  std::error_code error;
  std::filesystem::rename(temporary_, target_.path, error);
  if (error)
    throw InputError(destination_.string() + ": cannot move the output file into place (" + error.message() +
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

namespace fs = std::filesystem;

// The staged files (paths relative to `staging`), in a stable order, and the
// folders holding them.
void ListStaged(const fs::path& staging, std::vector<fs::path>& files, std::vector<fs::path>& folders) {
  for (auto entry = fs::recursive_directory_iterator(staging); entry != fs::recursive_directory_iterator();
       ++entry) {
    const fs::path relative = entry->path().lexically_relative(staging);
    if (entry->is_directory())
      folders.push_back(relative);
    else
      files.push_back(relative);
  }
  std::sort(files.begin(), files.end());
  std::sort(folders.begin(), folders.end());
}

// Refuses (before anything moves) a staged name that would replace what the
// folder holds: a folder where a file goes or the reverse always, a file
// unless `replace_existing` allows replacing regular files.
void CheckStagedNames(const fs::path& destination, const std::vector<fs::path>& files,
                      const std::vector<fs::path>& folders, bool replace_existing) {
  for (const fs::path& folder : folders) {
    std::error_code error;
    const fs::file_status status = fs::status(destination / folder, error);
    if (fs::exists(status) && !fs::is_directory(status))
      throw InputError("'" + (destination / folder).string() +
                       "' exists and is not a folder; napkin does not replace it.");
  }
  for (const fs::path& file : files) {
    const fs::path target = destination / file;
    CheckNotProtected(target);
    std::error_code error;
    const fs::file_status status = fs::symlink_status(target, error);
    if (!fs::exists(status)) continue;
    if (!fs::is_regular_file(status))
      throw InputError("'" + target.string() +
                       "' exists and is not a regular file; napkin does not replace it.");
    if (!replace_existing)
      throw InputError("'" + target.string() +
                       "' already exists; napkin does not replace it unless --force is given.");
  }
}

// `message` with the staging folder's name replaced by the destination's:
// the user named the destination, the staging folder is napkin's own.
std::string NamingDestination(std::string message, const fs::path& staging, const fs::path& destination) {
  const std::string from = staging.string();
  const std::string to = destination.string();
  for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
    message.replace(at, from.size(), to);
  return message;
}

}  // namespace

void WriteDirectoryAtomically(const fs::path& destination,
                              const std::function<void(const fs::path& directory)>& fill,
                              bool replace_existing) {
  std::error_code error;
  const bool created = fs::create_directories(destination, error);
  if (error)
    throw InputError(destination.string() + ": cannot create the output folder (" + error.message() + ").");
  if (!fs::is_directory(destination))
    throw InputError(destination.string() + ": exists and is not a folder.");
  // Inside the destination: the same file system, so every move is a rename,
  // and no other folder needs to be writable.
  const fs::path staging = destination / (".napkin-staging-" + RandomSuffix());
  fs::create_directory(staging, error);
  if (error)
    throw InputError(destination.string() + ": cannot create the output folder (" + error.message() + ").");
  try {
    fill(staging);
    std::vector<fs::path> files, folders;
    ListStaged(staging, files, folders);
    CheckStagedNames(destination, files, folders, replace_existing);
    for (const fs::path& folder : folders) fs::create_directories(destination / folder);
    for (const fs::path& file : files) {
      fs::rename(staging / file, destination / file, error);
      if (error)
        throw InputError((destination / file).string() + ": cannot move the output file into place (" +
                         error.message() + ").");
    }
    fs::remove_all(staging, error);  // staging's own, now empty, folders
  } catch (...) {
    fs::remove_all(staging, error);
    if (created) fs::remove(destination, error);  // only when empty: nothing else was there
    try {
      throw;
    } catch (const UsageError& usage) {
      throw UsageError(NamingDestination(usage.what(), staging, destination));
    } catch (const InputError& input) {
      throw InputError(NamingDestination(input.what(), staging, destination));
    }
  }
}

}  // namespace napkin::util
