#pragma once
// Zip archives as NHTSA distributes its test data (one test per archive,
// docs/formats.md "Zip archives"), read with libzip. Nothing is trusted:
// every member name must be a relative path that stays inside the archive
// (no absolute path, drive letter or ".." component), and a member is read
// into memory only within ceilings on its size, on the total read from the
// archive and on its compression ratio; a member that inflates to more (or
// fewer) bytes than its header declares, or whose CRC does not match, is
// refused. Every refusal is an InputError of one sentence naming the archive
// and the member.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

struct zip;  // libzip's zip_t

namespace napkin::formats {

struct ZipLimits {
  std::uint64_t max_member_bytes = std::uint64_t{512} << 20;  // one member, uncompressed
  std::uint64_t max_total_bytes = std::uint64_t{2} << 30;     // all members read, uncompressed
  // Uncompressed / compressed size above which a member is taken for a zip
  // bomb, once it is larger than ratio_floor_bytes (small files of equal
  // lines compress very well and are harmless).
  double max_ratio = 200.0;
  std::uint64_t ratio_floor_bytes = std::uint64_t{1} << 20;
  std::uint64_t max_members = 100'000;
};

struct ZipMember {
  std::uint64_t index = 0;
  std::string name;                   // as stored, '/' separated ('\\' read as '/')
  std::uint64_t size = 0;             // declared uncompressed size
  std::uint64_t compressed_size = 0;  // declared compressed size
  bool directory = false;             // name ends with '/'
};

// Why `name` cannot be a member's relative path (absolute, drive letter,
// "..", empty, control character), or nullopt when it can.
std::optional<std::string> UnsafeMemberName(std::string_view name);

class ZipArchive {
 public:
  // Opens `path` and checks its central directory against the local headers
  // and every member name. Throws InputError on a file that is not a zip
  // archive, a damaged one, too many members, an unsafe member name, or an
  // encrypted member.
  explicit ZipArchive(const std::filesystem::path& path, ZipLimits limits = {});
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::vector<ZipMember>& members() const { return members_; }

  // The member's bytes, decompressed in memory. Throws InputError (naming the
  // archive and the member) when the declared size is over a ceiling, the
  // compression ratio is that of a zip bomb, the data inflates beyond or
  // falls short of the declared size, or the data is corrupt (CRC).
  std::string Read(const ZipMember& member);

 private:
  std::string Where(const ZipMember& member) const;

  std::filesystem::path path_;
  ZipLimits limits_;
  ::zip* archive_ = nullptr;
  std::vector<ZipMember> members_;
  std::uint64_t total_read_ = 0;
};

// A member of an archive written in memory.
struct ZipMemberBytes {
  std::string name;  // '/' separated, relative
  std::string bytes;
};

// The zip archive of `members` (deflated, in the order given), as bytes in
// memory: how `napkin serve` sends a folder export (docs/serve.md). Every
// member is dated 2000-01-01 00:00 (DOS time, no time zone), so the same
// members give the same bytes.
std::string ZipArchiveBytes(const std::vector<ZipMemberBytes>& members);

}  // namespace napkin::formats
