#include "ingest/array_from_codes.h"

#include <map>
#include <set>

#include "common/error.h"
#include "util/text.h"

namespace napkin::ingest {
namespace {

// ISO/TS 13499 code characters (formats/isomme.h): 3-6 main location, 7-8 fine location 1,
// 9-10 fine location 2, 13-14 physical dimension, 15 direction.
bool IsHeadKinematic(std::string_view code) {
  return code.size() == 16 && util::EqualsIgnoreCase(code.substr(2, 4), "HEAD") &&
         (util::EqualsIgnoreCase(code.substr(12, 2), "AC") ||
          util::EqualsIgnoreCase(code.substr(12, 2), "AV"));
}

// The head CG as the "default" channel map reads it (config/channel-maps/default.json).
bool IsAtHeadCg(std::string_view code) {
  return util::EqualsIgnoreCase(code.substr(6, 2), "CG") || code.substr(6, 4) == "0000";
}

std::string AxisList(const std::set<char>& axes) {
  std::string list;
  for (const char axis : axes) {
    if (!list.empty()) list += axis == *axes.rbegin() ? " and " : ", ";
    list += static_cast<char>(axis - 'X' + 'x');
  }
  return list.empty() ? "no axis" : list;
}

struct HeadAxes {
  std::set<char> acceleration;
  std::set<char> angular_rate;
};

}  // namespace

std::string ArrayPresetFromCodes(const std::vector<formats::RawChannel>& channels,
                                 const std::string& test_name, const std::string& array_option) {
  const std::string prefix = "test " + test_name + ": ";
  const std::string give = "; give the array with " + array_option + ".";
  std::map<std::string, HeadAxes> axes_of_position;
  for (const formats::RawChannel& channel : channels) {
    const std::string code(util::Trim(channel.code));
    if (!IsHeadKinematic(code)) continue;
    const bool acceleration = util::EqualsIgnoreCase(code.substr(12, 2), "AC");
    const char* sensor = acceleration ? "accelerometer" : "angular-rate sensor";
    if (!IsAtHeadCg(code))
      throw UsageError(
          prefix + channel.Label() + " is a head " + sensor + " off the CG (fine location " +
          util::Quoted(code.substr(6, 2)) +
          "), where only the array's geometry says it sits: an array with arms needs its geometry"
          "; give it with " +
          array_option +
          " (e.g. denton-3222), and a channel map for the codes of the arms (--channel-map, e.g. "
          "nap-example).");
    const char direction = util::ToUpper(code.substr(14, 1)).front();
    if (direction != 'X' && direction != 'Y' && direction != 'Z')
      throw UsageError(prefix + channel.Label() + " is a head " + sensor + " along " +
                       util::Quoted(code.substr(14, 1)) + ", no body axis, so the codes define no array" +
                       give);
    HeadAxes& axes = axes_of_position[channel.position];
    (acceleration ? axes.acceleration : axes.angular_rate).insert(direction);
  }
  if (axes_of_position.empty())
    throw UsageError(prefix +
                     "no channel code names a head accelerometer at the CG (e.g. D0HEADCG0000ACXA), so the "
                     "codes define no array" +
                     give);
  std::string preset;
  std::string preset_position;
  const std::set<char> xyz = {'X', 'Y', 'Z'};
  for (const auto& [position, axes] : axes_of_position) {
    const std::string head = position.empty() ? "the head" : "the head at position " + position;
    if (axes.acceleration != xyz)
      throw UsageError(prefix + head + " has CG accelerometers along " + AxisList(axes.acceleration) +
                       ", and arrays from codes need x, y and z" + give);
    if (!axes.angular_rate.empty() && axes.angular_rate != xyz)
      throw UsageError(prefix + head + " has angular-rate sensors along " + AxisList(axes.angular_rate) +
                       ", and arrays from codes need none or x, y and z" + give);
    const std::string own = axes.angular_rate.empty() ? "3a-cg" : "6aw-cg";
    if (!preset.empty() && own != preset)
      throw UsageError(prefix + "the head at position " + preset_position + " is array " + preset + " and " +
                       head + " array " + own + ", and the heads of one test share its array" + give);
    preset = own;
    preset_position = position;
  }
  return preset;
}

}  // namespace napkin::ingest
