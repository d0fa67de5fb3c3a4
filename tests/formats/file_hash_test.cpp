#include "formats/file_hash.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "common/error.h"
#include "tests/support/test_support.h"
#include "util/sha256.h"

namespace napkin::formats {
namespace {

TEST(HashPathTest, FolderHashDependsOnNamesAndContent) {
  napkin::test_support::TempDir dir;
  std::filesystem::create_directories(dir / "t/Channel");
  std::ofstream(dir / "t/a.mme") << "x";
  std::ofstream(dir / "t/Channel/a.001") << "1\n2\n";
  const std::string before = HashPath(dir / "t");
  EXPECT_EQ(HashPath(dir / "t"), before);
  std::ofstream(dir / "t/Channel/a.001") << "1\n3\n";
  EXPECT_NE(HashPath(dir / "t"), before);
  EXPECT_EQ(HashPath(dir / "t/a.mme"), util::Sha256Hex("x"));
  EXPECT_THROW(HashPath(dir / "missing"), InputError);
}

}  // namespace
}  // namespace napkin::formats
