#pragma once
// What conditioning did to one channel of one test (docs/algorithms.md
// "Signal conditioning"; docs/formats.md "Conditioning record"): the record
// every result stores and `summary.json`, `query conditioning` and `report`
// show, so a number can be traced to the bias, filter and time base it was
// computed from.
#include <optional>
#include <string>
#include <vector>

#include "engine/array_geometry.h"

namespace napkin::engine {

struct ChannelConditioning {
  std::string channel;        // slot name
  double time_shift_s = 0.0;  // subtracted from every time stamp (config time.shift_s)
  // The mean subtracted (in the unit the array gives the slot; 0 when none)
  // and the times, after the shift, of the first and last sample it averaged;
  // no window when no bias was removed.
  double bias_removed = 0.0;
  std::optional<double> bias_window_start_s;
  std::optional<double> bias_window_end_s;
  // The CFC class napkin applied; none when the config asks for none, when
  // the slot feeds no sensor, or when the file records the channel as
  // already filtered at the requested class or a narrower one.
  std::optional<double> filter_cfc;
  // The class the file records the channel as already filtered at (ISO-MME
  // filter letter / "Channel frequency class", UDS-1992 FCUT); none = raw or
  // not recorded; kPrefilteredClassUnknown (0) = filtered at a class the file
  // does not name.
  std::optional<double> prefiltered_cfc;
  // Whether the requested filter was left out because of prefiltered_cfc.
  bool filter_skipped_prefiltered = false;
};

// The filter a channel got, in words: "CFC 1000", "none" or "none,
// prefiltered at CFC 1000", followed by " (prefiltered, class unknown)" for
// a channel filtered at a class the file does not name (docs/formats.md
// "Conditioning record").
std::string FilterDescription(const ChannelConditioning& record);

// The class a channel's samples are filtered at after conditioning: the
// class napkin applied, else the (named) class the file records; nullopt
// when the channel is unfiltered or its class unknown.
std::optional<double> FilteredClass(const ChannelConditioning& record);

// The class of the channels feeding the sensors of `kind` in `array` after
// conditioning, for what is derived from them: their FilteredClass when all
// have one (the widest when they differ); nullopt when one is unfiltered or
// of unknown class, or when no record is of such a sensor.
std::optional<double> FilteredClassOfKind(const std::vector<ChannelConditioning>& records,
                                          const ArrayGeometry& array, SensorKind kind);

}  // namespace napkin::engine
