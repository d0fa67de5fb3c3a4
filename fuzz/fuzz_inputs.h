#pragma once
// The fuzz targets of `make fuzz` (docs/architecture.md "Fuzzing"). Each
// target writes one input as the file (or test folder) a napkin parser reads
// and runs the parser through its public file entry point, as `import` and
// `transform` do (target `where`: the text of `query --where`). An input is
// either accepted or rejected with an InputError (`where`: a UsageError),
// the one-sentence error napkin prints; any other exception, a crash, a
// hang or a sanitizer report is a finding, and its input becomes a
// regression case (fuzz/regressions/<target>/, run by tests/fuzz/).
#include <string_view>
#include <vector>

namespace napkin::fuzz {

enum class Outcome { kAccepted, kRejected };

struct FuzzTarget {
  std::string_view name;  // e.g. "csv": fuzz/seeds/csv/, executable csv_fuzzer
  std::string_view what;  // the parser and entry point, for messages
  Outcome (*run)(std::string_view input);
};

// Every target, in the order `make fuzz` runs them.
const std::vector<FuzzTarget>& FuzzTargets();

// The target called `name`; throws std::invalid_argument for an unknown name.
const FuzzTarget& GetFuzzTarget(std::string_view name);

// The isomme_mme input is a whole ISO-MME test folder: the .mme file, then the
// .chn channel list, then the channel files .001, .002, ..., separated by NUL
// bytes (which text files never hold). A missing .chn or channel file is
// replaced by a valid one-channel default.
inline constexpr char kIsoMmePartSeparator = '\0';
inline constexpr std::size_t kIsoMmeMaxChannelFiles = 16;

}  // namespace napkin::fuzz
