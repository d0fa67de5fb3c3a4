#pragma once
// Atomic output files: every writer of napkin writes to a temporary file in
// the destination's folder and renames it over the destination only when
// everything was written and flushed, so a crash, a full disk or an exception
// never leaves a partial output file behind (rename(2) is atomic within one
// file system). The destination is resolved once by util/output_destination.h
// and everything after happens on the descriptor of its folder (openat,
// fstatat, renameat): a symbolic link is written through (the rename happens
// in its target's folder), a FIFO or character device is written straight
// into, "-" is standard output, and a protected file (the catalogue, the
// command's inputs) is refused, checked again on the opened folder right
// before the rename. A replaced file keeps its mode, and its owner and group
// where the process may set them; a new file gets the umask's mode.
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
  std::string temporary_;  // its name in the target's folder; empty when writing straight into the target
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Writes `destination` atomically with `write` filling the file.
void WriteFileAtomically(const std::filesystem::path& destination,
                         const std::function<void(AtomicFile&)>& write);

// Files written into a folder all at once (ISO-MME and UDS exports): `fill`
// writes them into a hidden staging folder inside `destination` (created when
// missing; opened once, and `fill` is given a path that reaches the opened
// staging folder whatever is renamed meanwhile); only when it has finished
// are they moved into place, beside whatever the folder already holds, by
// renames within one file system. Nothing in `destination` is removed: a
// staged file whose name is taken there is refused before any is moved,
// unless `replace_existing` (then a regular file of that name is replaced;
// a folder, link or device never is), and so is a subfolder on another file
// system (a link to elsewhere), where a rename cannot go. All or nothing: when
// a move fails, the files already moved are taken back and any file they
// replaced is restored; the staging folder, and `destination` when this call
// created it, are removed.
void WriteDirectoryAtomically(const std::filesystem::path& destination,
                              const std::function<void(const std::filesystem::path& directory)>& fill,
                              bool replace_existing = false);

// Tests only: the next WriteDirectoryAtomically fails its move number
// `move_index` (0-based) as a full or failing file system would; -1 clears.
void FailFolderMoveForTesting(int move_index);

}  // namespace napkin::util
