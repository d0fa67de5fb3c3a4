#pragma once
// Atomic output files: every writer of napkin writes to a temporary file in
// the destination's directory and renames it over the destination only when
// everything was written and flushed, so a crash, a full disk or an exception
// never leaves a partial output file behind (rename(2) is atomic within one
// file system). The destination is resolved by util/output_destination.h:
// a symbolic link is written through (the rename happens in its target's
// folder), a FIFO or character device is written straight into, "-" is
// standard output, and a protected file (the catalogue) is refused.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "util/output_destination.h"

namespace napkin::util {

// One output file being written. Write through file(); Commit() flushes,
// closes and renames; the destructor removes the temporary file when Commit()
// was not reached (e.g. an exception unwound the writer).
class AtomicFile {
 public:
  // Throws InputError naming `destination` when it is refused
  // (ResolveOutputDestination) or the temporary file cannot be created
  // (missing directory, no permission).
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
  std::filesystem::path destination_;  // as requested, for messages
  OutputDestination target_;
  std::filesystem::path temporary_;  // empty when writing straight into the target
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Writes `destination` atomically with `write` filling the file.
void WriteFileAtomically(const std::filesystem::path& destination,
                         const std::function<void(AtomicFile&)>& write);

// Files written into a folder all at once (ISO-MME and UDS exports): `fill`
// writes them into a hidden staging folder inside `destination` (created when
// missing); only when it has finished are they moved into place, beside
// whatever the folder already holds. Nothing in `destination` is removed: a
// staged file whose name is taken there is refused before any is moved,
// unless `replace_existing` (then a regular file of that name is replaced;
// a folder, link or device never is). On failure the staging folder, and
// `destination` when this call created it, are removed.
void WriteDirectoryAtomically(const std::filesystem::path& destination,
                              const std::function<void(const std::filesystem::path& directory)>& fill,
                              bool replace_existing = false);

}  // namespace napkin::util
