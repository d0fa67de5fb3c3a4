#pragma once
// Atomic output files: every writer of napkin writes to a temporary file in
// the destination's directory and renames it over the destination only when
// everything was written and flushed, so a crash, a full disk or an exception
// never leaves a partial output file behind (rename(2) is atomic within one
// file system).
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace napkin::formats {

// One output file being written. Write through file(); Commit() flushes,
// closes and renames; the destructor removes the temporary file when Commit()
// was not reached (e.g. an exception unwound the writer).
class AtomicFile {
 public:
  // Throws InputError naming `destination` when the temporary file cannot be
  // created (missing directory, no permission).
  explicit AtomicFile(std::filesystem::path destination);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::FILE* file() { return file_; }
  const std::filesystem::path& destination() const { return destination_; }

  void Write(std::string_view text);
  // printf-style formatted output.
  void Printf(const char* format, ...) __attribute__((format(printf, 2, 3)));
  // Throws InputError naming the destination on any write, flush or rename failure.
  void Commit();

 private:
  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Writes `destination` atomically with `write` filling the file.
void WriteFileAtomically(const std::filesystem::path& destination,
                         const std::function<void(AtomicFile&)>& write);

// A directory written atomically (ISO-MME test folders): `fill` populates a
// temporary sibling directory, which then replaces `destination` (an existing
// destination directory is replaced only after the new one is complete).
void WriteDirectoryAtomically(const std::filesystem::path& destination,
                              const std::function<void(const std::filesystem::path& directory)>& fill);

}  // namespace napkin::formats
