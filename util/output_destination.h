#pragma once
// Where an output goes, decided once for every writer of napkin
// (util/atomic_file.h; docs/formats.md "Output destinations"):
// - "-" is standard output;
// - a symbolic link is followed to the file it names (the link stays);
// - a FIFO or a character device (/dev/null, a terminal) is written straight
//   into: no temporary file, no rename, nothing replaced;
// - a regular file (or a new name) is written atomically beside its final
//   place and renamed over it;
// - a protected file (the catalogue and its SQLite side files) is never a
//   destination, by whatever name it is reached: compared by device and inode
//   (a symbolic link, hard link or "./" spelling), and by resolved path for a
//   side file that does not exist yet.
#include <filesystem>
#include <string>

namespace napkin::util {

struct OutputDestination {
  enum class Kind {
    kStandardOutput,  // "-"
    kStream,          // an existing FIFO or character device, opened and written as it is
    kFile,            // a regular file or a new name: written to a temporary sibling, then renamed
  };
  Kind kind = Kind::kFile;
  // The file written: the requested path with symbolic links followed (for
  // kFile the rename happens in this path's folder). Empty for standard output.
  std::filesystem::path path;
};

// The spelling of standard output in --out.
inline constexpr const char* kStandardOutputName = "-";

// Resolves `requested` as above. Throws InputError naming `requested` when it
// is protected, a folder, a block device or socket, or a loop of symbolic links.
OutputDestination ResolveOutputDestination(const std::filesystem::path& requested);

// Throws InputError naming `requested` when it is (or, not existing yet,
// resolves to) a protected file; else returns. For outputs that are not
// written through util::AtomicFile (a results catalogue).
void CheckNotProtected(const std::filesystem::path& requested);

// Marks `file` as never to be written by an output, e.g. the catalogue:
// `what` names it in the refusal ("the catalogue 'lab.db'"). Protection lasts
// for the process; the file need not exist yet.
void ProtectFromOutput(const std::filesystem::path& file, const std::string& what);

// Forgets every protected file (tests).
void ClearOutputProtection();

}  // namespace napkin::util
