#include "formats/derived_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "formats/csv.h"
#include "util/atomic_file.h"

namespace napkin::formats {

std::string DerivedJsonText(const engine::Kinematics& kinematics, const std::string& test_id) {
  using Json = nlohmann::ordered_json;
  Json channels = Json::object();
  for (const DerivedChannel& channel : DerivedChannels(kinematics)) {
    if (channel.values.size() == 0) {
      channels[channel.name] = nullptr;
      continue;
    }
    Json values = Json::array();
    for (Eigen::Index k = 0; k < channel.values.size(); ++k)
      values.push_back(std::isfinite(channel.values[k]) ? Json(channel.values[k]) : Json(nullptr));
    channels[channel.name] = std::move(values);
  }
  const Json object = {{"test_id", test_id}, {"channels", std::move(channels)}};
  return object.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

void WriteDerivedJson(const engine::Kinematics& kinematics, const std::string& test_id,
                      const std::filesystem::path& path) {
  const std::string text = DerivedJsonText(kinematics, test_id);
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) { file.Write(text); });
}

}  // namespace napkin::formats
