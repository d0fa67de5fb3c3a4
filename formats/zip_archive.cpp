#include "formats/zip_archive.h"

#include <zip.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "common/error.h"
#include "util/text.h"

namespace napkin::formats {
namespace {

std::string LibzipMessage(int code) {
  zip_error_t error;
  zip_error_init_with_code(&error, code);
  std::string message = zip_error_strerror(&error);
  zip_error_fini(&error);
  return message;
}

std::string Bytes(std::uint64_t bytes) { return std::to_string(bytes) + " bytes"; }

}  // namespace

std::optional<std::string> UnsafeMemberName(std::string_view name) {
  if (name.empty()) return "an empty name";
  for (const char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "a control character in its name";
  if (name.front() == '/' || name.front() == '\\') return "an absolute path";
  if (name.size() >= 2 && name[1] == ':') return "an absolute path (drive letter)";
  std::size_t start = 0;
  while (start <= name.size()) {
    std::size_t end = name.find_first_of("/\\", start);
    if (end == std::string_view::npos) end = name.size();
    if (name.substr(start, end - start) == "..") return "a \"..\" component (a path leaving the archive)";
    start = end + 1;
  }
  return std::nullopt;
}

ZipArchive::ZipArchive(const std::filesystem::path& path, ZipLimits limits) : path_(path), limits_(limits) {
  int code = 0;
  archive_ = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code);
  if (archive_ == nullptr)
    throw InputError(path_.string() + ": not a readable zip archive (" + util::ToLower(LibzipMessage(code)) +
                     ").");
  try {
    const zip_int64_t count = zip_get_num_entries(archive_, 0);
    if (count < 0) throw InputError(path_.string() + ": not a readable zip archive.");
    if (static_cast<std::uint64_t>(count) > limits_.max_members)
      throw InputError(path_.string() + ": the zip archive lists " + std::to_string(count) +
                       " members, more than the " + std::to_string(limits_.max_members) + " napkin reads.");
    members_.reserve(static_cast<std::size_t>(count));
    for (zip_int64_t i = 0; i < count; ++i) {
      zip_stat_t stat;
      zip_stat_init(&stat);
      if (zip_stat_index(archive_, static_cast<zip_uint64_t>(i), 0, &stat) != 0 ||
          (stat.valid & ZIP_STAT_NAME) == 0 || (stat.valid & ZIP_STAT_SIZE) == 0 ||
          (stat.valid & ZIP_STAT_COMP_SIZE) == 0)
        throw InputError(path_.string() + ": member " + std::to_string(i + 1) +
                         " of the zip archive has an unreadable header (" +
                         util::ToLower(zip_error_strerror(zip_get_error(archive_))) + ").");
      ZipMember member;
      member.index = static_cast<std::uint64_t>(i);
      member.name = stat.name;
      std::replace(member.name.begin(), member.name.end(), '\\', '/');
      member.size = stat.size;
      member.compressed_size = stat.comp_size;
      member.directory = !member.name.empty() && member.name.back() == '/';
      if (const std::optional<std::string> unsafe = UnsafeMemberName(stat.name))
        throw InputError(path_.string() + ": member \"" + member.name + "\" has " + *unsafe +
                         "; napkin refuses the archive.");
      if ((stat.valid & ZIP_STAT_ENCRYPTION_METHOD) != 0 && stat.encryption_method != ZIP_EM_NONE)
        throw InputError(Where(member) + " is encrypted; napkin reads unencrypted archives only.");
      if ((stat.valid & ZIP_STAT_COMP_METHOD) != 0 && !member.directory &&
          !zip_compression_method_supported(stat.comp_method, 0))
        throw InputError(Where(member) + " uses compression method " + std::to_string(stat.comp_method) +
                         ", which this libzip cannot decompress.");
      members_.push_back(std::move(member));
    }
  } catch (...) {
    zip_discard(archive_);
    throw;
  }
}

ZipArchive::~ZipArchive() {
  if (archive_ != nullptr) zip_discard(archive_);  // opened read-only: nothing to write back
}

std::string ZipArchive::Where(const ZipMember& member) const {
  return path_.string() + ": member \"" + member.name + "\"";
}

std::string ZipArchive::Read(const ZipMember& member) {
  if (member.size > limits_.max_member_bytes)
    throw InputError(Where(member) + " declares " + Bytes(member.size) + " uncompressed, more than the " +
                     Bytes(limits_.max_member_bytes) + " napkin reads from one member.");
  if (member.size > limits_.max_total_bytes - std::min(total_read_, limits_.max_total_bytes))
    throw InputError(Where(member) + " would bring the archive's uncompressed total above " +
                     Bytes(limits_.max_total_bytes) + ".");
  if (member.size > limits_.ratio_floor_bytes &&
      static_cast<double>(member.size) > limits_.max_ratio * static_cast<double>(member.compressed_size)) {
    char ratio[32];
    std::snprintf(ratio, sizeof(ratio), "%.0f",
                  static_cast<double>(member.size) /
                      static_cast<double>(std::max<std::uint64_t>(member.compressed_size, 1)));
    throw InputError(Where(member) + " inflates " + ratio + " times (" + Bytes(member.compressed_size) +
                     " to " + Bytes(member.size) + "), the ratio of a zip bomb.");
  }

  zip_file_t* file = zip_fopen_index(archive_, member.index, 0);
  if (file == nullptr)
    throw InputError(Where(member) + " cannot be opened (" +
                     util::ToLower(zip_error_strerror(zip_get_error(archive_))) + ").");
  std::string bytes;
  bytes.reserve(static_cast<std::size_t>(member.size));
  // Read one byte more than declared: data that inflates beyond its declared
  // size is refused rather than followed.
  const std::uint64_t wanted = member.size + 1;
  char buffer[1 << 16];
  std::string failure;
  while (bytes.size() < wanted) {
    const zip_uint64_t chunk = std::min<std::uint64_t>(sizeof(buffer), wanted - bytes.size());
    const zip_int64_t got = zip_fread(file, buffer, chunk);
    if (got < 0) {
      failure = util::ToLower(zip_error_strerror(zip_file_get_error(file)));
      break;
    }
    if (got == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(got));
  }
  zip_fclose(file);
  if (!failure.empty()) throw InputError(Where(member) + " is corrupt (" + failure + ").");
  if (bytes.size() > member.size)
    throw InputError(Where(member) + " inflates beyond the " + Bytes(member.size) +
                     " its header declares, like a zip bomb.");
  if (bytes.size() < member.size)
    throw InputError(Where(member) + " holds " + Bytes(bytes.size()) + " of the " + Bytes(member.size) +
                     " its header declares (a damaged archive).");
  total_read_ += bytes.size();
  return bytes;
}

std::string ZipArchiveBytes(const std::vector<ZipMemberBytes>& members) {
  // libzip removes an archive without members on closing it: the empty archive is its end of
  // central directory record alone (APPNOTE.TXT 4.3.16), 22 bytes.
  if (members.empty()) return std::string("PK\x05\x06", 4) + std::string(18, '\0');
  // Failing here is running out of memory or a bug (the archive is napkin's own, in memory).
  const auto failed = [](const std::string& what, zip_error_t* error) {
    const std::string message = "cannot build a zip archive in memory (" + what + ": " +
                                (error != nullptr ? zip_error_strerror(error) : "libzip failed") + ").";
    return std::runtime_error(message);
  };
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (buffer == nullptr) throw failed("buffer", &error);
  zip_t* archive = zip_open_from_source(buffer, ZIP_TRUNCATE, &error);
  if (archive == nullptr) {
    zip_source_free(buffer);
    throw failed("open", &error);
  }
  zip_source_keep(buffer);  // read after zip_close
  // 2000-01-01 00:00:00 as DOS date and time: year since 1980 << 9 | month << 5 | day.
  constexpr zip_uint16_t kDosDate = (20 << 9) | (1 << 5) | 1;
  for (const ZipMemberBytes& member : members) {
    // The bytes live in `members` until zip_close.
    zip_source_t* source = zip_source_buffer(archive, member.bytes.data(), member.bytes.size(), 0);
    const zip_int64_t index =
        source == nullptr ? -1 : zip_file_add(archive, member.name.c_str(), source, ZIP_FL_ENC_UTF_8);
    if (index < 0 || zip_file_set_dostime(archive, static_cast<zip_uint64_t>(index), 0, kDosDate, 0) != 0 ||
        zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 0) != 0) {
      if (source != nullptr && index < 0) zip_source_free(source);
      const std::runtime_error problem = failed(member.name, zip_get_error(archive));
      zip_discard(archive);
      zip_source_free(buffer);
      throw problem;
    }
  }
  if (zip_close(archive) != 0) {
    const std::runtime_error problem = failed("close", zip_get_error(archive));
    zip_discard(archive);
    zip_source_free(buffer);
    throw problem;
  }
  std::string bytes;
  if (zip_source_open(buffer) != 0) {
    zip_source_free(buffer);
    throw failed("read", nullptr);
  }
  zip_int64_t size = -1;
  if (zip_source_seek(buffer, 0, SEEK_END) == 0) size = zip_source_tell(buffer);
  zip_int64_t read = -1;
  if (size >= 0 && zip_source_seek(buffer, 0, SEEK_SET) == 0) {
    bytes.resize(static_cast<std::size_t>(size));
    read = zip_source_read(buffer, bytes.data(), static_cast<zip_uint64_t>(size));
  }
  zip_source_close(buffer);
  zip_source_free(buffer);
  if (size < 0 || read != size) throw failed("read", nullptr);
  return bytes;
}

}  // namespace napkin::formats
