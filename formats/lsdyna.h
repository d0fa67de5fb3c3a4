#pragma once
// Load curves for finite-element head models (docs/formats.md "LS-DYNA export"):
// the LS-DYNA keyword file with six *DEFINE_CURVE (fixed-frame CG velocity X,
// Y, Z and angular velocity X, Y, Z) and six *BOUNDARY_PRESCRIBED_MOTION_RIGID
// cards (DOF 1, 2, 3, 5, 6, 7; VAD = 0), and the report's legacy LC_FILE.DAT
// (section 2.1.2, Appendix B listing).
#include <array>
#include <filesystem>
#include <optional>
#include <string_view>

#include "engine/kinematics.h"
#include "engine/vocabulary.h"
#include "util/atomic_file.h"

namespace napkin::formats {

enum class LsDynaUnits {
  kSi,       // m, s (rad/s)
  kEnglish,  // in, s (rad/s), as the report's anatomic brain model
};

inline constexpr std::array<engine::NamedValue<LsDynaUnits>, 2> kLsDynaUnitsNames{
    {{LsDynaUnits::kSi, "si"}, {LsDynaUnits::kEnglish, "english"}}};
inline constexpr std::array<LsDynaUnits, 2> kLsDynaUnits = engine::ValuesOf(kLsDynaUnitsNames);

// The one spelling of each unit system ("si", "english"; `napkin export
// --units`), and its inverse (nullopt for an unknown name).
constexpr const auto& NamesOf(LsDynaUnits) { return kLsDynaUnitsNames; }

struct LsDynaOptions {
  int part_id = 1;         // rigid part driven by the curves (--part)
  int first_curve_id = 1;  // LCIDs first_curve_id ... first_curve_id + 5
  LsDynaUnits units = LsDynaUnits::kSi;
};

// Abscissae are times from the first sample (the simulation starts at 0).
void WriteLsDynaKeyword(const engine::Kinematics& kinematics, const std::filesystem::path& path,
                        const LsDynaOptions& options = {});
// The same into an output already opened (several outputs committed together).
void WriteLsDynaKeyword(const engine::Kinematics& kinematics, util::AtomicFile& file,
                        const LsDynaOptions& options = {});

// LC_FILE.DAT as LC_COMP wrote it: per curve a comment line ("c load curve
// for x velocity", ...), the line " lcd   <n>   <npts>" (format 1x,'lcd',3x,
// i,3x,i4), then time-value pairs in format 2(3x,1pe10.3); velocities in
// in/s, angular velocities in rad/s, time (j-1)*del.
void WriteLcFile(const engine::Kinematics& kinematics, const std::filesystem::path& path);

}  // namespace napkin::formats
