#pragma once
// The folder of `napkin demo`: it holds nothing but what the demo wrote. A
// stamp file lists the demo's files, so a later demo knows which files it may
// replace (docs/formats.md "Output destinations"); a user's file is never
// removed.
#include <filesystem>
#include <vector>

namespace napkin::cli {

// Makes `dir` ready for the demo: created when missing; else it must be
// empty or hold nothing but a previous demo's stamped files (with the SQLite
// side files of its catalogue `catalogue`, a name in `dir`), which are
// removed. Throws InputError naming the first other entry. Returns whether a
// previous demo's catalogue was there.
bool PrepareDemoFolder(const std::filesystem::path& dir, const std::filesystem::path& catalogue);

// Writes the stamp listing `files` (relative to `dir`), the files this demo
// writes, before it writes any (so an interrupted demo's output is its own too).
void WriteDemoStamp(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& files);

}  // namespace napkin::cli
