#pragma once
// Reading files with one-sentence errors naming the file: only regular files
// (never a FIFO, device or socket, also behind a symbolic link), of at most a
// size ceiling (docs/formats.md "Names, limits and escaping"), and JSON on top.
#include <sys/stat.h>
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "util/unique_fd.h"

namespace napkin::formats {

// Size ceilings: test data files (CSV, ISO-MME channel files, UDS-1992
// files) and the small JSON definitions (arrays, configs, channel maps).
inline constexpr std::uintmax_t kMaxDataFileBytes = std::uintmax_t{1} << 30;   // 1 GiB
inline constexpr std::uintmax_t kMaxJsonFileBytes = std::uintmax_t{16} << 20;  // 16 MiB

// Parses `path` as JSON (at most kMaxJsonFileBytes). Throws InputError
// "<path>: ..." when it cannot be read or is not valid JSON (with the
// parser's line/column).
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

// Reads a whole regular file of at most `max_bytes` into memory. Throws
// InputError naming the file when it does not exist, is a symbolic-link
// loop, is not a regular file, is larger than `max_bytes` or cannot be read.
std::string ReadWholeFile(const std::filesystem::path& path, std::uintmax_t max_bytes = kMaxDataFileBytes);

// Opens `path` for reading (O_NONBLOCK: a FIFO never blocks the open) and
// refuses, by fstat of that descriptor, anything but a regular file of at most
// `max_bytes`: for readers that read the file they judged more than once
// (formats::ReadModelFile). Throws InputError (the sentences of ReadWholeFile).
util::UniqueFd OpenRegularFile(const std::filesystem::path& path, std::uintmax_t max_bytes);

// `path` opened for reading as every bounded input is (O_RDONLY; O_NONBLOCK:
// a FIFO never blocks the open; O_NOCTTY, O_CLOEXEC), with fstat's answer on
// that descriptor: what OpenRegularFile judges, and a caller with rules and
// sentences of its own (the inbox's sidecars, the service's token file).
// `error` is the errno of the open or the fstat that failed, 0 when both
// succeeded. Throws nothing.
struct OpenedForReading {
  util::UniqueFd fd;
  struct stat status {};
  int error = 0;
};
OpenedForReading OpenForReading(const std::filesystem::path& path);

// Like ReadWholeFile, but hands the content to `consume` in chunks.
void ReadFileInChunks(const std::filesystem::path& path, std::uintmax_t max_bytes,
                      const std::function<void(std::string_view chunk)>& consume);

// What a file of `mode` is, for a sentence refusing it: "a folder", "a FIFO
// (named pipe)", "a character device", "a block device", "a socket".
const char* FileTypeName(mode_t mode);

// Reads the open descriptor `fd` to its end, at most `max_bytes` (a file
// that grows past them while being read is refused): the one read loop of
// every bounded input, for callers that judge the descriptor they opened
// (fstat) by rules of their own. `name` begins the sentences ("sidecar
// 'P'", "P:"), `ceiling` says whose limit it is ("a sidecar may have").
// Throws InputError naming the file on a read error or growth.
void ReadDescriptorInChunks(int fd, std::uintmax_t max_bytes, const std::string& name,
                            const std::string& ceiling,
                            const std::function<void(std::string_view chunk)>& consume);
std::string ReadDescriptor(int fd, std::uintmax_t max_bytes, const std::string& name,
                           const std::string& ceiling);

// Throws InputError (the sentences of ReadWholeFile) unless `path` is a
// regular file of at most `max_bytes`; opens nothing.
void CheckRegularFile(const std::filesystem::path& path, std::uintmax_t max_bytes = kMaxDataFileBytes);

}  // namespace napkin::formats
