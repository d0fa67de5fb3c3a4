#include "formats/lsdyna.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.h"
#include "engine/units.h"
#include "util/atomic_file.h"

namespace napkin::formats {
namespace {

void RequireSamples(const engine::Kinematics& kinematics, const std::filesystem::path& path) {
  if (kinematics.size() < 2)
    throw InputError(path.string() + ": cannot write load curves of fewer than two samples.");
}

// A real in a 20-column field: 12 significant digits, always fits.
void AppendReal20(std::string& out, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%20.12e", value);
  out += buffer;
}

}  // namespace

void WriteLsDynaKeyword(const engine::Kinematics& kinematics, util::AtomicFile& file,
                        const LsDynaOptions& options) {
  RequireSamples(kinematics, file.destination());
  const Eigen::Index n = kinematics.size();
  const double length_scale = options.units == LsDynaUnits::kSi ? 1.0 : 1.0 / engine::kMetresPerInch;
  const char* length_unit = options.units == LsDynaUnits::kSi ? "m" : "in";
  struct Curve {
    const engine::Series3* series;
    int component;
    double scale;
    int dof;  // BOUNDARY_PRESCRIBED_MOTION_RIGID: 1-3 translation x-z, 5-7 rotation about x-z
    std::string title;
  };
  const Curve curves[6] = {
      {&kinematics.vel_fixed, 0, length_scale, 1,
       std::string("CG velocity X, fixed frame (") + length_unit + "/s)"},
      {&kinematics.vel_fixed, 1, length_scale, 2,
       std::string("CG velocity Y, fixed frame (") + length_unit + "/s)"},
      {&kinematics.vel_fixed, 2, length_scale, 3,
       std::string("CG velocity Z, fixed frame (") + length_unit + "/s)"},
      {&kinematics.omega_fixed, 0, 1.0, 5, "angular velocity about fixed X (rad/s)"},
      {&kinematics.omega_fixed, 1, 1.0, 6, "angular velocity about fixed Y (rad/s)"},
      {&kinematics.omega_fixed, 2, 1.0, 7, "angular velocity about fixed Z (rad/s)"},
  };
  std::string out;
  out += "*KEYWORD\n";
  out += "$ napkin: 6-DOF head CG motion, SAE J211 axes (x forward, y right, z down); units ";
  out += options.units == LsDynaUnits::kSi ? "m, s, rad\n" : "in, s, rad\n";
  char line[256];
  for (int i = 0; i < 6; ++i) {
    const Curve& curve = curves[i];
    out += "$ " + curve.title + "\n";
    out += "*DEFINE_CURVE\n";
    out += "$     LCID      SIDR       SFA       SFO      OFFA      OFFO    DATTYP\n";
    std::snprintf(line, sizeof(line), "%10d%10d%10.1f%10.1f%10.1f%10.1f%10d\n", options.first_curve_id + i, 0,
                  1.0, 1.0, 0.0, 0.0, 0);
    out += line;
    out += "$                 A1                  O1\n";
    for (Eigen::Index k = 0; k < n; ++k) {
      AppendReal20(out, kinematics.time_s[k] - kinematics.time_s[0]);
      AppendReal20(out, (*curve.series)(k, curve.component) * curve.scale);
      out += '\n';
    }
    file.Write(out);
    out.clear();
  }
  for (int i = 0; i < 6; ++i) {
    out += "*BOUNDARY_PRESCRIBED_MOTION_RIGID\n";
    out += "$      PID       DOF       VAD      LCID        SF       VID     DEATH     BIRTH\n";
    std::snprintf(line, sizeof(line), "%10d%10d%10d%10d%10.1f%10d%10.3e%10.1f\n", options.part_id,
                  curves[i].dof, 0, options.first_curve_id + i, 1.0, 0, 1e28, 0.0);
    out += line;
  }
  out += "*END\n";
  file.Write(out);
}

void WriteLsDynaKeyword(const engine::Kinematics& kinematics, const std::filesystem::path& path,
                        const LsDynaOptions& options) {
  util::WriteFileAtomically(path,
                            [&](util::AtomicFile& file) { WriteLsDynaKeyword(kinematics, file, options); });
}

void WriteLcFile(const engine::Kinematics& kinematics, const std::filesystem::path& path) {
  RequireSamples(kinematics, path);
  const Eigen::Index n = kinematics.size();
  const double inch_per_metre = 1.0 / engine::kMetresPerInch;
  struct Curve {
    const engine::Series3* series;
    int component;
    double scale;
    const char* comment;
  };
  // Formats 7301-7306 of the LC_COMP listing.
  const Curve curves[6] = {
      {&kinematics.vel_fixed, 0, inch_per_metre, "c load curve for x velocity"},
      {&kinematics.vel_fixed, 1, inch_per_metre, "c load curve for y velocity"},
      {&kinematics.vel_fixed, 2, inch_per_metre, "c load curve for z velocity"},
      {&kinematics.omega_fixed, 0, 1.0, "c load curve for angular vel. about x axis"},
      {&kinematics.omega_fixed, 1, 1.0, "c load curve for angular vel. about y axis"},
      {&kinematics.omega_fixed, 2, 1.0, "c load curve for angular vel. about z axis"},
  };
  util::WriteFileAtomically(path, [&](util::AtomicFile& file) {
    for (int i = 0; i < 6; ++i) {
      file.Printf("%s\n lcd   %d   %4lld\n", curves[i].comment, i + 1, static_cast<long long>(n));
      for (Eigen::Index k = 0; k < n; ++k)  // format 6100: 2(3x,1pe10.3)
        file.Printf("   %10.3E   %10.3E\n", kinematics.time_s[k] - kinematics.time_s[0],
                    (*curves[i].series)(k, curves[i].component) * curves[i].scale);
    }
  });
}

}  // namespace napkin::formats
