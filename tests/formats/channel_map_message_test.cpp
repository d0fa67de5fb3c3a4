// The sentence AssignSlots gives when no channel of a test matches a slot of the channel map: it
// names what the slot's entry would have matched (its codes, then SENATT and AXIS), as the user
// must fix either the files or the map (docs/formats.md "ISO-MME (ISO/TS 13499) input").
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/error.h"
#include "formats/channel_map.h"
#include "tests/support/reference_arrays.h"

namespace napkin::formats {
namespace {

using ::testing::StrEq;
using ::testing::ThrowsMessage;

// The message for a test without channels, the array's first slot mapped by `entry`.
void ExpectNoChannelMessage(const ChannelMapEntry& entry, const std::string& matched) {
  const engine::ArrayGeometry array = test_support::Ideal3222();
  ChannelMap map;
  map.name = "bench";
  map.source = "bench.json";
  for (const engine::Sensor& sensor : array.sensors) map.slots.emplace_back(sensor.slot, entry);
  const std::string slot = array.sensors.front().slot;
  EXPECT_THAT([&] { AssignSlots({}, array, map, "t1"); },
              ThrowsMessage<InputError>(StrEq("test t1: no channel matches slot \"" + slot + "\" (" +
                                              matched + ") of channel map \"bench\".")));
}

TEST(ChannelMapMessage, NamesTheEntrysCodesThenItsSensorAttachmentAndAxis) {
  ExpectNoChannelMessage({{"11HEAD0000H3ACXA", "11HEADCG0000ACXP"}, "HEAD CG", "XL", ""},
                         "11HEAD0000H3ACXA or 11HEADCG0000ACXP, or SENATT \"HEAD CG\" AXIS \"XL\"");
}

TEST(ChannelMapMessage, NamesASensorAttachmentWithoutAxisAlone) {
  ExpectNoChannelMessage({{}, "HEAD CG", "", ""}, "SENATT \"HEAD CG\"");
}

TEST(ChannelMapMessage, NamesASingleCode) {
  ExpectNoChannelMessage({{"11HEAD0000H3ACXA"}, "", "", ""}, "11HEAD0000H3ACXA");
}

}  // namespace
}  // namespace napkin::formats
