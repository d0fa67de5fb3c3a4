#include "engine/channel_conditioning.h"

#include <algorithm>
#include <sstream>

#include "engine/signals.h"

namespace napkin::engine {

std::string FilterDescription(const ChannelConditioning& record) {
  std::ostringstream text;
  if (record.filter_cfc)
    text << "CFC " << *record.filter_cfc;
  else if (record.filter_skipped_prefiltered)
    text << "none, prefiltered at CFC " << *record.prefiltered_cfc;
  else
    text << "none";
  // Never "none, prefiltered ...": that prefix means a skipped filter (db/catalogue_results.cpp).
  if (record.prefiltered_cfc == kPrefilteredClassUnknown) text << " (prefiltered, class unknown)";
  return text.str();
}

std::optional<double> FilteredClass(const ChannelConditioning& record) {
  if (record.filter_cfc) return record.filter_cfc;
  if (record.prefiltered_cfc && *record.prefiltered_cfc != kPrefilteredClassUnknown)
    return record.prefiltered_cfc;
  return std::nullopt;
}

std::optional<double> FilteredClassOfKind(const std::vector<ChannelConditioning>& records,
                                          const ArrayGeometry& array, SensorKind kind) {
  std::optional<double> widest;
  bool any = false;
  for (const ChannelConditioning& record : records) {
    const auto sensor =
        std::find_if(array.sensors.begin(), array.sensors.end(),
                     [&](const Sensor& candidate) { return candidate.slot == record.channel; });
    if (sensor == array.sensors.end() || sensor->kind != kind) continue;
    const std::optional<double> cfc = FilteredClass(record);
    if (!cfc) return std::nullopt;
    widest = any ? std::max(*widest, *cfc) : *cfc;
    any = true;
  }
  return widest;
}

}  // namespace napkin::engine
