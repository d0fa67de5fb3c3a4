#include "formats/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <random>
#include <system_error>

#include "common/error.h"

namespace napkin::formats {
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

AtomicFile::AtomicFile(std::filesystem::path destination) : destination_(std::move(destination)) {
  temporary_ = TemporarySibling(destination_);
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr)
    throw InputError(destination_.string() + ": cannot create the output file (" + std::strerror(errno) +
                     ").");
  // A large buffer: writers emit many short numbers.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_) {
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
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed)
    throw InputError(destination_.string() + ": write failed (" + std::strerror(errno) + ").");
  std::error_code error;
  std::filesystem::rename(temporary_, destination_, error);
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

void WriteDirectoryAtomically(const std::filesystem::path& destination,
                              const std::function<void(const std::filesystem::path& directory)>& fill) {
  const std::filesystem::path temporary = TemporarySibling(destination);
  std::error_code error;
  std::filesystem::create_directories(temporary, error);
  if (error)
    throw InputError(destination.string() + ": cannot create the output folder (" + error.message() + ").");
  try {
    fill(temporary);
    if (std::filesystem::exists(destination)) {
      if (!std::filesystem::is_directory(destination))
        throw InputError(destination.string() + ": exists and is not a folder.");
      const std::filesystem::path old = TemporarySibling(destination);
      std::filesystem::rename(destination, old, error);
      if (error)
        throw InputError(destination.string() + ": cannot replace the existing folder (" + error.message() +
                         ").");
      std::filesystem::rename(temporary, destination, error);
      if (error) {
        std::filesystem::rename(old, destination);  // put the previous folder back
        throw InputError(destination.string() + ": cannot move the output folder into place (" +
                         error.message() + ").");
      }
      std::filesystem::remove_all(old, error);
    } else {
      std::filesystem::rename(temporary, destination, error);
      if (error)
        throw InputError(destination.string() + ": cannot move the output folder into place (" +
                         error.message() + ").");
    }
  } catch (...) {
    std::filesystem::remove_all(temporary, error);
    throw;
  }
}

}  // namespace napkin::formats
