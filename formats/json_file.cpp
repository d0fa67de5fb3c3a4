#include "formats/json_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/error.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

std::string Named(const std::filesystem::path& path) { return util::EscapeControl(path.string()); }

std::string SizeText(std::uintmax_t bytes) {
  if (bytes >= (std::uintmax_t{1} << 20) && bytes % (std::uintmax_t{1} << 20) == 0)
    return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

[[noreturn]] void ThrowCannotOpen(const std::filesystem::path& path, int error) {
  if (error == ELOOP)
    throw InputError(Named(path) + ": is a loop of symbolic links; point the link at a real file.");
  throw InputError(Named(path) + ": cannot open the file (" + std::strerror(error) + ").");
}

void CheckStat(const std::filesystem::path& path, const struct stat& status, std::uintmax_t max_bytes) {
  if (!S_ISREG(status.st_mode))
    throw InputError(Named(path) + ": is " + FileTypeName(status.st_mode) +
                     ", not a regular file; napkin reads only regular files.");
  if (static_cast<std::uintmax_t>(status.st_size) > max_bytes)
    throw InputError(Named(path) + ": is " + std::to_string(status.st_size) + " bytes, more than the " +
                     SizeText(max_bytes) + " napkin reads from one file.");
}

}  // namespace

const char* FileTypeName(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

void ReadDescriptorInChunks(int fd, std::uintmax_t max_bytes, const std::string& name,
                            const std::string& ceiling,
                            const std::function<void(std::string_view chunk)>& consume) {
  char buffer[1 << 16];
  std::uintmax_t total = 0;
  for (;;) {
    const ssize_t count = ::read(fd, buffer, sizeof(buffer));
    if (count < 0) {
      if (errno == EINTR) continue;
      throw InputError(name + " cannot be read (" + std::strerror(errno) + ").");
    }
    if (count == 0) break;
    total += static_cast<std::uintmax_t>(count);
    if (total > max_bytes)  // the file grew while being read
      throw InputError(name + " grew beyond the " + SizeText(max_bytes) + " " + ceiling +
                       " while being read.");
    consume(std::string_view(buffer, static_cast<std::size_t>(count)));
  }
}

std::string ReadDescriptor(int fd, std::uintmax_t max_bytes, const std::string& name,
                           const std::string& ceiling) {
  std::string content;
  ReadDescriptorInChunks(fd, max_bytes, name, ceiling,
                         [&](std::string_view chunk) { content.append(chunk); });
  return content;
}

void CheckRegularFile(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) ThrowCannotOpen(path, errno);
  CheckStat(path, status, max_bytes);
}

OpenedForReading OpenForReading(const std::filesystem::path& path) {
  // O_NONBLOCK: opening a FIFO for reading must not wait for a writer; the
  // type is judged on the open descriptor before anything is read.
  OpenedForReading opened;
  opened.fd = util::UniqueFd(::open(path.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!opened.fd.valid() || ::fstat(opened.fd.get(), &opened.status) != 0) opened.error = errno;
  return opened;
}

util::UniqueFd OpenRegularFile(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  OpenedForReading opened = OpenForReading(path);
  if (opened.error != 0) ThrowCannotOpen(path, opened.error);
  CheckStat(path, opened.status, max_bytes);
  return std::move(opened.fd);
}

void ReadFileInChunks(const std::filesystem::path& path, std::uintmax_t max_bytes,
                      const std::function<void(std::string_view chunk)>& consume) {
  const util::UniqueFd file = OpenRegularFile(path, max_bytes);
  ReadDescriptorInChunks(file.get(), max_bytes, Named(path) + ":", "napkin reads from one file", consume);
}

std::string ReadWholeFile(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  std::string content;
  ReadFileInChunks(path, max_bytes, [&](std::string_view chunk) { content.append(chunk); });
  return content;
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  const std::string text = ReadWholeFile(path, kMaxJsonFileBytes);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    // A syntax error (parse_error) or a number beyond double's range
    // (out_of_range 406, found by fuzz/). nlohmann's message starts with
    // "[json.exception.parse_error.101] parse error at line L, column C: ..."
    // or "[json.exception.out_of_range.406] number overflow parsing ...".
    std::string what = error.what();
    const std::size_t start = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && start != std::string::npos) what = what.substr(start + 2);
    if (!what.empty() && what.back() != '.') what += '.';
    throw InputError(Named(path) + ": not valid JSON (" +
                     util::Abbreviated(what.substr(0, what.size() - 1), 200) + ").");
  }
}

}  // namespace napkin::formats
