#pragma once
// `export --format uds`: a test's derived channels as the UDS-1992 files the
// report's own program writes (report Appendix B, LC_COMP output; section
// 2.1): F<test>AM00.00X/Y/Z CG acceleration along fixed axes (G'S),
// B<test>ROTV.00X/Y/Z angular velocity about body axes (RADIANS/SEC),
// F<test>ROTA.00X/Y/Z angular acceleration about fixed axes
// (RADIANS/SEC**2), F<test>DCOS.011/.022/.033 angles between body and fixed
// axes (DEGREES), F<test>ROTD.00X/Y/Z roll, pitch, yaw (DEGREES),
// F<test>ROTV.00X/Y/Z angular velocity about fixed axes (RADIANS/SEC) and
// F<test>VM00.00X/Y/Z CG velocity along fixed axes (IN/SEC).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/array_geometry.h"
#include "engine/channel_conditioning.h"
#include "engine/kinematics.h"
#include "engine/processing.h"
#include "formats/uds1992.h"

namespace napkin::formats {

// The filter classes the derived channels are computed from (nullopt:
// unfiltered), as FCUT, the cut-off in Hz of the class (NHTSA's
// doc/UDS_Vars.txt; engine::J211CutoffOfClass), 0 for unfiltered channels.
struct UdsExportFilters {
  std::optional<double> linear_cfc;   // the accelerometers: AM00, VM00
  std::optional<double> angular_cfc;  // ROTV, ROTA, DCOS, ROTD (rate sensors, else accelerometers)
};

// The classes of a result's derived channels from its conditioning record
// (engine::FilteredClassOfKind; angular channels from the rate sensors when
// the array has them, else from the accelerometers), or from `configured`
// for a result stored without a record (before schema version 5).
UdsExportFilters UdsFiltersOfResult(const std::vector<engine::ChannelConditioning>& conditioning,
                                    const engine::ArrayGeometry& array,
                                    const engine::FilterConfig& configured);

// Writes the 21 files into `folder` (created if needed; each file written
// atomically) in `form`. `test_number` is <test> in the names. Returns the
// paths written, in the order above. Throws InputError when the test number
// cannot name files, the time grid does not start at a whole sample
// (NFP = t0 / DEL), or a value cannot be stored in `form`.
std::vector<std::filesystem::path> WriteDerivedUds(const engine::Kinematics& kinematics,
                                                   const std::filesystem::path& folder,
                                                   const std::string& test_number, UdsNumberForm form,
                                                   const UdsExportFilters& filters = {});

}  // namespace napkin::formats
