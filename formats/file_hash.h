#pragma once
// The hash that identifies an imported file or folder in the catalogue
// (idempotent import, ingest/content_hash.h): SHA-256 (util/sha256.h) of the
// bytes as they are on disk.

#include <filesystem>
#include <string>

namespace napkin::formats {

// Hash of a file's bytes, or of a folder's files (relative path and bytes, in
// sorted path order). Throws InputError naming the path when unreadable.
std::string HashPath(const std::filesystem::path& path);

}  // namespace napkin::formats
