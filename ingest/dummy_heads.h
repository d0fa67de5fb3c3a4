#pragma once
// Reading one import input into the dummy heads it holds (docs/formats.md
// "Several dummies in one test"): a real ISO-MME or UDS-1992 test records
// several dummies (driver at position 11, passenger at 13, ...); each head
// the channel map finds is one catalogue test. Also what the files say about
// the test (formats::TestInfo), the UDS-1992 initial velocity, and notes
// such as channels cropped to their common span.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/signals.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/test_info.h"
#include "ingest/discovery.h"

namespace napkin::ingest {

// For every sensor of the array, the channel feeding it, for one dummy.
struct DummyHead {
  std::string position;  // formats::RawChannel::position shared by its channels ("" if none)
  std::vector<std::size_t> channel_of_sensor;
};

struct DummyHeadSearch {
  std::vector<DummyHead> heads;       // in position order
  std::vector<std::string> warnings;  // positions whose channels do not cover the array
};

// The dummy heads `map` finds among `channels`. When the matched channels
// name one position (or none), this is AssignSlots over all channels and
// its errors. With several positions, each position's channels are assigned
// on their own; a position that cannot feed every slot is left out with a
// warning, and when none can, the first position's error is thrown.
DummyHeadSearch FindDummyHeads(const std::vector<formats::RawChannel>& channels,
                               const engine::ArrayGeometry& array, const formats::ChannelMap& map,
                               const std::string& test_name);

// The initial CG velocity of one head from the files (UDS-1992 INIVEL: the
// velocity of the sensor along the channel's own axis).
struct FileInitialVelocity {
  // Body axes; nullopt when no channel feeding the head records one.
  std::optional<Eigen::Vector3d> velocity_body_mps;
  // One sentence per channel whose INIVEL is not used, naming it and why.
  std::vector<std::string> unused;
};

// Every point of a rigid body without initial rotation has the same
// velocity, so each linear accelerometer sensing along a body axis gives
// that axis's CG velocity, wherever it sits; with an initial angular
// velocity omega the sensor at r moves at v_CG + omega x r, which is taken
// off (docs/formats.md "UDS-1992 input"). Per axis the sensor nearest the
// CG is used; a channel whose INIVEL differs from it, an angular-rate
// channel and a sensor along no body axis are reported in `unused`.
FileInitialVelocity InitialVelocityBody(const std::vector<formats::RawChannel>& channels,
                                        const std::vector<std::size_t>& channel_of_sensor,
                                        const engine::ArrayGeometry& array,
                                        const Eigen::Vector3d& omega_body_radps = Eigen::Vector3d::Zero());

// One dummy head of an input, read and checked, ready to store.
struct HeadSignals {
  std::string position;  // "" when the input names none (CSV, Table 2-1 order, one unnamed dummy)
  engine::TestSignals signals;
  formats::TestInfo info;  // with the sensors feeding the slots, where the files record them
  std::optional<Eigen::Vector3d> initial_velocity_body_mps;
  std::string channel_map;                     // map used; "" for CSV and Table 2-1 order
  std::vector<std::string> notes;              // recorded with the test (e.g. cropped spans)
  std::optional<InputFormat> archived_format;  // the format inside a zip archive
};

struct InputHeads {
  std::vector<HeadSignals> heads;  // the heads to import
  // The array the heads were read for: the one given, or the one the channel codes define.
  engine::ArrayGeometry array;
  bool array_from_codes = false;  // no array was given; the codes defined it (ingest/array_from_codes.h)
  // The test id the files give (DTS SLICEWare's Test ID); nullopt: the input's name.
  std::optional<std::string> test_id;
  // The input holds several dummy heads: each test id gets "/<position>"
  // and each content hash the position.
  bool several = false;
  std::vector<std::string> warnings;  // ignored CSV columns, positions left out
};

struct HeadReadOptions {
  // The array, or null: the channel codes define it where the format has codes
  // (InputFormatEntry::array_from_codes), else the input is refused naming `array_option`.
  const engine::ArrayGeometry* array = nullptr;
  std::string array_option = "--array";              // how the front end names the array in sentences
  std::filesystem::path config_dir;                  // the presets (empty: formats::DefaultConfigDir())
  const formats::ChannelMap* channel_map = nullptr;  // --channel-map, or null
  const formats::ChannelMap* default_map = nullptr;  // the "default" preset
  formats::CsvColumnMap csv_columns;                 // --column and the map's "column" entries
  std::optional<std::string> position;               // --position: take this head only
  // Why one head is expected ("--test-id names one test"): several are refused saying so.
  std::optional<std::string> one_test_expected;
  // The head's initial angular velocity (body axes), for INIVEL off the CG.
  Eigen::Vector3d initial_omega_body_radps = Eigen::Vector3d::Zero();
};

// Reads `input` into its dummy heads through its format's reader
// (ingest/input_formats.h); a zip archive is read through ArchiveTest, its
// messages naming "<archive>:<member>". Throws InputError (one sentence) for
// a file problem, for no array given where the codes define none, for
// --position naming a position the input lacks, and when several heads are
// found where one test is expected (--test-id without --position).
InputHeads ReadInputHeads(const ImportInput& input, const HeadReadOptions& options,
                          const std::string& test_name);

// The CSV columns a read takes slots from: the channel map's "column" entries,
// then `column_options` (`--column SLOT=NAME`, formats::ParseCsvColumnOptions),
// which win (docs/formats.md "CSV input").
formats::CsvColumnMap CsvColumnsOf(const formats::ChannelMap* map,
                                   const std::vector<std::string>& column_options);

}  // namespace napkin::ingest
