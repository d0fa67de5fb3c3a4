#pragma once
// The array a test's ISO/TS 13499 channel codes define, when no array is
// given (docs/formats.md "Arrays from channel codes"): head accelerometers
// (`..HEAD......AC..`) and angular-rate sensors (`AV`) all at the head CG
// (fine location `CG`, or `0000` as the "default" channel map reads it)
// along X, Y and Z are the preset `6aw-cg`; the three accelerometers alone
// are `3a-cg`. Sensors off the CG (the arms of a nine-accelerometer array)
// sit where only the array's geometry says: then no array follows from the
// codes, and the sentence says so.
#include <string>
#include <vector>

#include "formats/channel_map.h"

namespace napkin::ingest {

// The preset the head channels of `channels` define (every position the
// same), or throws UsageError (the array must be given: exit 2, as a
// missing --array): one sentence starting with `test_name`,
// naming the channel at fault and why, ending with what to give instead
// (`array_option`, e.g. "--array").
std::string ArrayPresetFromCodes(const std::vector<formats::RawChannel>& channels,
                                 const std::string& test_name, const std::string& array_option);

}  // namespace napkin::ingest
