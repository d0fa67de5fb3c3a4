#include "ingest/content_hash.h"

#include <cstdint>
#include <span>

#include "formats/file_hash.h"
#include "util/sha256.h"

namespace napkin::ingest {

std::string InputContentHash(const ImportInput& input) {
  const InputFormatEntry& format = FormatEntry(input.format);
  if (format.span != TestSpan::kFileGroup) return formats::HashPath(input.source);
  util::Sha256 hash;
  hash.Update(std::string(format.name) + " group\n");  // UDS-1992: "uds-1992 group\n"
  for (const std::filesystem::path& file : input.files) hash.Update(formats::HashPath(file) + "\n");
  return hash.HexDigest();
}

std::string SyntheticContentHash(const db::ArrayRow& array, const synth::SyntheticTest& test) {
  util::Sha256 hash;
  hash.Update("napkin synthetic test\n");
  hash.Update(array.definition_hash);
  for (const std::string& slot : test.signals.slots) {
    hash.Update("\n");
    hash.Update(slot);
  }
  auto update = [&](const double* values, std::size_t count) {
    hash.Update(
        std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(values), count * sizeof(double)));
  };
  const engine::InitialState& initial = test.initial;
  const double header[11] = {test.signals.dt_s,
                             test.signals.t0_s,
                             initial.orientation_rad[0],
                             initial.orientation_rad[1],
                             initial.orientation_rad[2],
                             initial.velocity_fixed_mps[0],
                             initial.velocity_fixed_mps[1],
                             initial.velocity_fixed_mps[2],
                             initial.omega_body_radps[0],
                             initial.omega_body_radps[1],
                             initial.omega_body_radps[2]};
  update(header, 11);
  update(test.signals.samples.data(), static_cast<std::size_t>(test.signals.samples.size()));
  return hash.HexDigest();
}

}  // namespace napkin::ingest
