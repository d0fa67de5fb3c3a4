#include "fuzz/fuzz_inputs.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "app/limits.h"
#include "app/where_parser.h"
#include "common/error.h"
#include "db/catalogue.h"
#include "engine/array_geometry.h"
#include "formats/array_json.h"
#include "formats/channel_map.h"
#include "formats/csv.h"
#include "formats/dts_slice_csv.h"
#include "formats/isomme.h"
#include "formats/model_curves.h"
#include "formats/processing_config_json.h"
#include "formats/uds1992.h"
#include "ingest/dummy_heads.h"
#include "serve/inbox.h"

namespace napkin::fuzz {
namespace {

namespace fs = std::filesystem;

// A private folder under $TMPDIR for the files of the current input, removed at exit.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    std::string pattern = (fs::temp_directory_path() / "napkin-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("napkin fuzz: cannot create a scratch folder " + pattern + " (" +
                               std::strerror(errno) + ").");
    path_ = pattern;
  }
  ~ScratchDirectory() {
    std::error_code error;
    fs::remove_all(path_, error);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

const fs::path& Scratch() {
  static const ScratchDirectory kDirectory;
  return kDirectory.path();
}

void WriteFile(const fs::path& path, std::string_view bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error("napkin fuzz: cannot write " + path.string() + ".");
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  if (std::fclose(file) != 0 || !written)
    throw std::runtime_error("napkin fuzz: cannot write " + path.string() + ".");
}

// The array and channel map the import is most often given for nine-accelerometer tests.
const engine::ArrayGeometry& NineAccelerometerArray() {
  static const engine::ArrayGeometry kArray = formats::LoadArray("denton-3222");
  return kArray;
}
const formats::ChannelMap& NineAccelerometerMap() {
  static const formats::ChannelMap kMap = formats::LoadChannelMap("nap-example");
  return kMap;
}

// Runs `parse`; an InputError is the parser's rejection.
template <typename Parse>
Outcome Attempt(Parse&& parse) {
  try {
    parse();
    return Outcome::kAccepted;
  } catch (const InputError&) {
    return Outcome::kRejected;
  }
}

Outcome Either(Outcome a, Outcome b) {
  return a == Outcome::kAccepted || b == Outcome::kAccepted ? Outcome::kAccepted : Outcome::kRejected;
}

// Each channel's unit as the import reads it (formats::ParseSignalUnit).
void ParseUnits(const std::vector<formats::RawChannel>& channels) {
  for (const formats::RawChannel& channel : channels) formats::ParseSignalUnit(channel.unit, channel.Label());
}

Outcome RunCsv(std::string_view input) {
  const fs::path path = Scratch() / "signals.csv";
  WriteFile(path, input);
  const Outcome any_columns = Attempt([&] { formats::ReadSignalsCsv(path); });
  const Outcome array_columns = Attempt([&] { formats::ReadSignalsCsv(path, &NineAccelerometerArray()); });
  return Either(any_columns, array_columns);
}

constexpr std::string_view kDefaultMme =
    "Data format                 :ISO-MME\n"
    "Version                     :1.6\n"
    "Test number                 :FUZZ-1\n"
    "Number of test objects      :1\n";
constexpr std::string_view kDefaultChn =
    "Instrumentation standard    :ISO 6487\n"
    "Number of channels          :1\n"
    "Name of channel 001         :11HEADCG0000ACXA / Head cg_x\n";
constexpr std::string_view kDefaultChannel =
    "Channel code                :11HEADCG0000ACXA\n"
    "Name of the channel         :Head cg_x\n"
    "Sampling interval           :0.0001\n"
    "Unit                        :g\n"
    "Time of first sample        :0\n"
    "Number of samples           :3\n"
    "0\n1.5\n-2\n";

// Reads the test folder as `import` does: the test, each channel's unit, and
// the signals of the nine-accelerometer array when the channels cover it.
Outcome ReadIsoMmeFolder(const fs::path& folder) {
  return Attempt([&] {
    const formats::IsoMmeTest test = formats::ReadIsoMme(folder);
    ParseUnits(test.channels);
    const std::string test_name = test.TestNumber();
    if (test.channels.size() >= NineAccelerometerArray().sensors.size()) {
      Attempt([&] {
        formats::AssembleSignals(
            test.channels,
            formats::AssignSlots(test.channels, NineAccelerometerArray(), NineAccelerometerMap(), test_name),
            NineAccelerometerArray(), test_name);
      });
    }
  });
}

Outcome RunIsoMmeChannel(std::string_view input) {
  static const fs::path kFolder = [] {
    fs::path path = Scratch() / "isomme_channel";
    fs::create_directories(path / "Channel");
    WriteFile(path / "FUZZ.mme", kDefaultMme);
    WriteFile(path / "Channel" / "FUZZ.chn", kDefaultChn);
    return path;
  }();
  WriteFile(kFolder / "Channel" / "FUZZ.001", input);
  return ReadIsoMmeFolder(kFolder);
}

Outcome RunIsoMmeMme(std::string_view input) {
  std::vector<std::string_view> parts;
  for (std::size_t start = 0;;) {
    const std::size_t end = input.find(kIsoMmePartSeparator, start);
    parts.push_back(
        input.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos || parts.size() == 2 + kIsoMmeMaxChannelFiles) break;
    start = end + 1;
  }
  const fs::path folder = Scratch() / "isomme_mme";
  fs::remove_all(folder);
  fs::create_directories(folder / "Channel");
  WriteFile(folder / "FUZZ.mme", parts[0]);
  WriteFile(folder / "Channel" / "FUZZ.chn", parts.size() > 1 ? parts[1] : kDefaultChn);
  if (parts.size() <= 2) {
    WriteFile(folder / "Channel" / "FUZZ.001", kDefaultChannel);
  } else {
    for (std::size_t i = 2; i < parts.size(); ++i) {
      char suffix[24];
      std::snprintf(suffix, sizeof(suffix), ".%03zu", i - 1);
      WriteFile(folder / "Channel" / (std::string("FUZZ") + suffix), parts[i]);
    }
  }
  return ReadIsoMmeFolder(folder);
}

Outcome RunUds1992(std::string_view input) {
  const fs::path path = Scratch() / "FUZZ.001";
  WriteFile(path, input);
  return Attempt([&] {
    const formats::RawChannel channel = formats::ToRawChannel(formats::ReadUds1992(path), path);
    ParseUnits({channel});
  });
}

// The input as a DTS SLICEWare CSV export read as `import` reads it (ingest::ReadInputHeads):
// its channels, the array its codes define and the head's signals; and for the 6aw-cg array given.
Outcome RunDtsSliceCsv(std::string_view input) {
  const fs::path path = Scratch() / "export.csv";
  WriteFile(path, input);
  static const engine::ArrayGeometry kSixDx = formats::LoadArray("6aw-cg");
  static const formats::ChannelMap kDefaultMap = formats::LoadChannelMap("default");
  const ingest::ImportInput test{ingest::InputFormat::kDtsSliceCsv, "FUZZ", path, {}};
  const auto read = [&](const engine::ArrayGeometry* array) {
    return Attempt([&] {
      ingest::HeadReadOptions options;
      options.array = array;
      options.default_map = &kDefaultMap;
      ingest::ReadInputHeads(test, options, "FUZZ");
    });
  };
  const Outcome channels = Attempt([&] { ParseUnits(formats::ReadDtsSliceCsv(path).channels); });
  return Either(channels, Either(read(nullptr), read(&kSixDx)));
}

Outcome RunArrayJson(std::string_view input) {
  const fs::path path = Scratch() / "array.json";
  WriteFile(path, input);
  return Attempt([&] { formats::ReadArrayJson(path); });
}

Outcome RunProcessingConfigJson(std::string_view input) {
  const fs::path path = Scratch() / "processing.json";
  WriteFile(path, input);
  return Attempt([&] { formats::CanonicalProcessingConfig(formats::ReadProcessingConfig(path)); });
}

Outcome RunChannelMapJson(std::string_view input) {
  const fs::path path = Scratch() / "channel-map.json";
  WriteFile(path, input);
  return Attempt([&] { formats::ReadChannelMap(path); });
}

Outcome RunLimitsJson(std::string_view input) {
  const fs::path path = Scratch() / "limits.json";
  WriteFile(path, input);
  return Attempt([&] { app::LoadLimits(path.string()); });
}

// The input as the model file of `correlate --model`: a nodout, an LS-DYNA keyword file or a model
// CSV, told by its content as app/correlation.cpp tells them (keyword and nodout in m, s, kg),
// read through its descriptor as ReadModelFile opens it. Read once keeping every curve and once
// keeping none: both must read the same curves (a curve not kept is checked all the same), else a
// finding.
Outcome RunModelCurves(std::string_view input) {
  const fs::path path = Scratch() / "model";
  WriteFile(path, input);
  const formats::ModelUnits units;
  return Attempt([&] {
    const formats::ModelFile file = formats::ReadModelFile(path);
    const auto read = [&](const formats::KeepCurve& keep) {
      if (file.head.find("n o d a l   p r i n t") != std::string::npos)
        return formats::ReadNodout(file, units, keep);
      if (file.head.starts_with("*") || file.head.find("\n*") != std::string::npos)
        return formats::ReadLsDynaCurves(file, units, keep);
      return formats::ReadModelCsv(file, keep);
    };
    const formats::ModelCurves every = read([](const std::string&) { return true; });
    const formats::ModelCurves none = read([](const std::string&) { return false; });
    if (every.names != none.names || !none.kept.empty() || every.kept.size() != every.names.size())
      throw std::logic_error("napkin fuzz: the model's curves differ with the curves kept.");
  });
}

// The input as the napkin.json sidecar of an inbox's variant folder (serve/inbox.h), read and its
// names resolved as the inbox does before importing a test below it.
Outcome RunSidecar(std::string_view input) {
  const fs::path inbox = Scratch() / "inbox";
  const fs::path folder = inbox / "series" / "variant";
  fs::create_directories(folder);
  WriteFile(folder / "napkin.json", input);
  return Attempt([&] { serve::CheckSidecarNames(serve::ReadSidecars(inbox, folder)); });
}

// The input as `query KIND --where`, for every KIND: parsed, and when the
// parser accepts it, run on an empty in-memory catalogue (every accepted
// expression must also run: docs/formats.md "Query filters"). A UsageError
// is the rejection; SQLite refusing the SQL (a DatabaseError) is a finding.
Outcome RunWhere(std::string_view input) {
  static db::Catalogue catalogue = db::Catalogue::Open(":memory:");
  Outcome outcome = Outcome::kRejected;
  for (const db::QueryKindSpec& kind : db::QueryKinds()) {
    if (kind.rows_of != kind.kind) continue;  // the same rows as another kind's
    try {
      db::QueryRequest request;
      request.where.push_back(app::ParseWhereExpression(input, db::QueryFields(kind.kind)));
      catalogue.Query(kind.kind, request);
      outcome = Outcome::kAccepted;
    } catch (const UsageError&) {
    }
  }
  return outcome;
}

}  // namespace

const std::vector<FuzzTarget>& FuzzTargets() {
  static const std::vector<FuzzTarget> kTargets = {
      {"csv", "formats::ReadSignalsCsv (any columns, and the denton-3222 array)", RunCsv},
      {"isomme_channel", "formats::ReadIsoMme, one ISO-MME channel file", RunIsoMmeChannel},
      {"isomme_mme", "formats::ReadIsoMme, AssignSlots, AssembleSignals: .mme, .chn and channel files",
       RunIsoMmeMme},
      {"uds1992", "formats::ReadUds1992, one UDS-1992 file", RunUds1992},
      {"dts_slice_csv", "formats::ReadDtsSliceCsv and ingest::ReadInputHeads, one DTS SLICEWare CSV export",
       RunDtsSliceCsv},
      {"array_json", "formats::ReadArrayJson", RunArrayJson},
      {"processing_config_json", "formats::ReadProcessingConfig", RunProcessingConfigJson},
      {"channel_map_json", "formats::ReadChannelMap", RunChannelMapJson},
      {"where", "app::ParseWhereExpression and db::Catalogue::Query (query --where, every kind)", RunWhere},
      {"limits_json", "app::LoadLimits", RunLimitsJson},
      {"model_curves",
       "formats::ReadModelFile, ReadModelCsv, ReadLsDynaCurves, ReadNodout (correlate --model)",
       RunModelCurves},
      {"sidecar", "serve::ReadSidecars and CheckSidecarNames (an inbox's napkin.json)", RunSidecar},
  };
  return kTargets;
}

const FuzzTarget& GetFuzzTarget(std::string_view name) {
  for (const FuzzTarget& target : FuzzTargets())
    if (target.name == name) return target;
  throw std::invalid_argument("napkin fuzz: no fuzz target " + std::string(name) + ".");
}

}  // namespace napkin::fuzz
