// util/text.h's encoding helpers (issue 19 item 7; docs/formats.md "Names,
// limits and escaping", "Text encoding"): strict UTF-8 validation as JSON
// needs it, ISO-8859-1 conversion, names of unknown encoding refused, and
// escaping that always yields UTF-8. Every case is written out by hand from
// RFC 3629 and the ISO-8859-1 code chart.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"
#include "util/text.h"
#include "util/utf8.h"

namespace napkin::formats {
namespace {

TEST(IsValidUtf8, AcceptsWhatRfc3629AllowsAndNothingElse) {
  for (const std::string& valid : {std::string(""), std::string("plain ASCII"), std::string("M\xc3\xbcller"),
                                   std::string("\xe2\x82\xac"),      // U+20AC
                                   std::string("\xed\x9f\xbf"),      // U+D7FF, last before the surrogates
                                   std::string("\xf0\x90\x80\x80"),  // U+10000
                                   std::string("\xf4\x8f\xbf\xbf"),  // U+10FFFF
                                   std::string("a\0b", 3)}) {        // NUL is a character
    EXPECT_TRUE(util::IsValidUtf8(valid)) << valid;
    EXPECT_NO_THROW((void)nlohmann::json(valid).dump()) << valid;  // what JSON output needs
  }
  for (const std::string& invalid : {std::string("M\xfcller"),         // ISO-8859-1 ü
                                     std::string("bad\xff"),           //
                                     std::string("\xc0\xaf"),          // overlong '/'
                                     std::string("\xe0\x80\xaf"),      // overlong '/'
                                     std::string("\xed\xa0\x80"),      // surrogate U+D800
                                     std::string("\xf4\x90\x80\x80"),  // above U+10FFFF
                                     std::string("\xf5\x80\x80\x80"),  //
                                     std::string("\xe2\x82"),          // cut short
                                     std::string("\x80"),              // lone continuation byte
                                     std::string("\xc3\xbc\xc3")}) {   // cut short at the end
    EXPECT_FALSE(util::IsValidUtf8(invalid)) << invalid;
    // The surrogate and overlong forms are exactly what nlohmann refuses too.
    EXPECT_THROW((void)nlohmann::json(invalid).dump(), nlohmann::json::type_error) << invalid;
  }
}

TEST(Latin1ToUtf8, EachByteIsItsCodePoint) {
  EXPECT_EQ(util::Latin1ToUtf8("M\xfcller K\xf6ln \xa9\xff"), "M\xc3\xbcller K\xc3\xb6ln \xc2\xa9\xc3\xbf");
  EXPECT_EQ(util::Latin1ToUtf8("ascii"), "ascii");
  // ToUtf8: valid UTF-8 is kept (napkin's own exports), anything else is ISO-8859-1.
  EXPECT_EQ(util::ToUtf8("M\xc3\xbcller"), "M\xc3\xbcller");
  EXPECT_EQ(util::ToUtf8("M\xfcller"), "M\xc3\xbcller");
  // A surrogate's bytes are not UTF-8: read as ISO-8859-1, so the result is valid.
  EXPECT_EQ(util::ToUtf8("\xed\xa0\x80"), "\xc3\xad\xc2\xa0\xc2\x80");
}

TEST(CheckName, RefusesNamesThatAreNotUtf8ShowingTheBytesEscaped) {
  EXPECT_NO_THROW(util::CheckName("--variant", "M\xc3\xbcller"));
  try {
    util::CheckName("--variant", "bad\xff");
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("--variant 'bad\\xff' is not valid UTF-8", 0), 0u)
        << error.what();
    EXPECT_TRUE(util::IsValidUtf8(error.what())) << error.what();
  }
  EXPECT_THROW(util::CheckUtf8("the path", "/data/\xed\xa0\x80.csv"), InputError);
}

TEST(EscapeControl, WritesBytesThatAreNotUtf8AsHexEscapes) {
  EXPECT_EQ(util::EscapeControl("M\xfcller"), "M\\xfcller");
  EXPECT_EQ(util::EscapeControl("M\xc3\xbcller\xff"), "M\xc3\xbcller\\xff");
  EXPECT_EQ(util::EscapeControl("\xed\xa0\x80"), "\\xed\\xa0\\x80");
  EXPECT_EQ(util::EscapeControl("\xe2\x82"), "\\xe2\\x82");
  EXPECT_EQ(util::EscapeControl("\xf0\x90\x80\x80 ok"), "\xf0\x90\x80\x80 ok");
  EXPECT_EQ(util::EscapeControl("a\x1b[31m\xc2\x9b"), "a\\x1b[31m\\u009b");  // control characters as before
  for (const std::string& text :
       {std::string("\xff\xfe"), std::string("x\xc3"), std::string("\xf4\x90\x80\x80")})
    EXPECT_TRUE(util::IsValidUtf8(util::EscapeControl(text))) << text;
}

}  // namespace
}  // namespace napkin::formats
