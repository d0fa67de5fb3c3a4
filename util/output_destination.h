#pragma once
// Where an output goes, decided once for every writer of napkin, on what is
// actually opened (util/atomic_file.h; docs/formats.md "Output destinations"):
// - "-" is standard output;
// - the folder that holds the destination's name is opened once; every later
//   step (examining the name, creating the temporary file, the rename) works
//   on that descriptor (openat, fstatat, renameat), so a folder or link
//   swapped in by another process after the decision is never written;
// - a symbolic link is followed to the file it names, once, relative to the
//   folder that holds the link (the link stays);
// - a FIFO or a character device (/dev/null, a terminal) is opened without
//   following links, checked to be one after opening, and written straight
//   into: no temporary file, no rename, nothing replaced;
// - a regular file (or a new name) is written to a temporary file beside it
//   and renamed over it;
// - a protected file (the catalogue and its SQLite side files, a command's
//   own inputs) is never a destination, by whatever name it is reached:
//   compared by device and inode of the file, and by the device and inode of
//   its folder with its name (a side file that does not exist yet).
#include <sys/stat.h>

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

#include "util/unique_fd.h"

namespace napkin::util {

// A name inside a folder that is open: what an output decides on.
struct OpenedEntry {
  UniqueFd folder;             // the folder holding the name, opened once
  std::string name;            // the entry's name in `folder` (no '/')
  std::filesystem::path path;  // the entry's path with links followed, for messages
  // The entry as it was when examined (not following a link); absent when
  // there is no such entry yet.
  std::optional<struct stat> status;
};

// Opens the folder holding `requested` and examines its last component,
// following a symbolic link there once per link (relative to the folder that
// holds it; 40 links at most, as the kernel). Throws InputError naming
// `requested` when the folder cannot be opened (missing, not a folder, no
// permission) or the links loop.
OpenedEntry OpenEntry(const std::filesystem::path& requested);

struct OutputDestination {
  enum class Kind {
    kStandardOutput,  // "-"
    kStream,          // an existing FIFO or character device, opened and written as it is
    kFile,            // a regular file or a new name: written to a temporary sibling, then renamed
  };
  Kind kind = Kind::kFile;
  // The file written: the requested path with symbolic links followed (for
  // messages and tests). Empty for standard output.
  std::filesystem::path path;
  // The folder and name written (not for standard output).
  OpenedEntry entry;
};

// The spelling of standard output in --out.
inline constexpr const char* kStandardOutputName = "-";

// Resolves `requested` as above. Throws InputError naming `requested` when it
// is protected, a folder, a block device or socket, or a loop of symbolic
// links; UsageError when it is empty.
OutputDestination ResolveOutputDestination(const std::filesystem::path& requested);

// Throws (as ProtectFromOutput says) naming `shown` when `entry` is a
// protected file: its folder and name, or the file it is.
void CheckNotProtected(const OpenedEntry& entry, const std::string& shown);
// The same for a path: throws when `requested` is (or, not existing yet,
// would be) a protected file; else returns.
void CheckNotProtected(const std::filesystem::path& requested);

// Whether a protected file is refused as bad input (exit 1: the catalogue) or
// as a usage error (exit 2: the command's own inputs and other outputs).
enum class Refusal { kInput, kUsage };

// Marks `file` as never to be written by an output, e.g. the catalogue:
// `what` names it in the refusal ("the catalogue 'lab.db'"). Protection lasts
// for the process; the file need not exist yet.
void ProtectFromOutput(const std::filesystem::path& file, const std::string& what,
                       Refusal refusal = Refusal::kInput);

// Forgets every protected file (tests).
void ClearOutputProtection();

// Refuses (UsageError, exit 2) two outputs of one command that name the same
// file by any spelling, e.g. `--out x --summary x`: the second would replace
// the first. Standard output and streams (FIFOs, character devices) are not
// compared; "-" twice is for the command to refuse. `outputs` pairs each
// option with its value; empty values are skipped.
void CheckDistinctOutputs(const std::initializer_list<std::pair<std::string, std::string>>& outputs);

// The temporary name napkin writes `name` under before renaming it into
// place: ".NAME.tmp-<16 hex digits>", with NAME shortened (at a UTF-8
// character boundary) so the whole fits the 255 bytes a name may have
// whenever `name` does.
std::string TemporaryNameFor(const std::string& name);
// Whether `candidate` is such a temporary name of `name` (a stale one left by
// a killed writer). For a name cut short, any name with the same first bytes
// matches too.
bool IsTemporaryNameOf(const std::string& candidate, const std::string& name);

}  // namespace napkin::util
