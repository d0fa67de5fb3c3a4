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
#include <string>
#include <vector>

#include "engine/kinematics.h"
#include "formats/uds1992.h"

namespace napkin::formats {

// Writes the 21 files into `folder` (created if needed; each file written
// atomically) in `form`. `test_number` is <test> in the names. Returns the
// paths written, in the order above. Throws InputError when the test number
// cannot name files, the time grid does not start at a whole sample
// (NFP = t0 / DEL), or a value cannot be stored in `form`.
std::vector<std::filesystem::path> WriteDerivedUds(const engine::Kinematics& kinematics,
                                                   const std::filesystem::path& folder,
                                                   const std::string& test_number, UdsNumberForm form);

}  // namespace napkin::formats
