#include "formats/uds_export.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "engine/units.h"
#include "util/text.h"

namespace napkin::formats {

UdsExportFilters UdsFiltersOfResult(const std::vector<engine::ChannelConditioning>& conditioning,
                                    const engine::ArrayGeometry& array,
                                    const engine::FilterConfig& configured) {
  const bool rate_sensors =
      std::any_of(array.sensors.begin(), array.sensors.end(),
                  [](const engine::Sensor& s) { return s.kind == engine::SensorKind::kAngularRate; });
  UdsExportFilters filters;
  if (conditioning.empty()) {
    filters.linear_cfc = configured.linear_cfc;
    filters.angular_cfc = rate_sensors ? configured.angular_rate_cfc : configured.linear_cfc;
    return filters;
  }
  filters.linear_cfc = engine::FilteredClassOfKind(conditioning, array, engine::SensorKind::kLinear);
  filters.angular_cfc =
      rate_sensors ? engine::FilteredClassOfKind(conditioning, array, engine::SensorKind::kAngularRate)
                   : filters.linear_cfc;
  return filters;
}

std::vector<std::filesystem::path> WriteDerivedUds(const engine::Kinematics& kinematics,
                                                   const std::filesystem::path& folder,
                                                   const std::string& test_number, UdsNumberForm form,
                                                   const UdsExportFilters& filters) {
  const Eigen::Index n = kinematics.size();
  if (n < 2) throw InputError(folder.string() + ": cannot export fewer than two samples.");
  if (test_number.empty() || test_number.find_first_of("/\\") != std::string::npos)
    throw InputError(folder.string() + ": \"" + test_number + "\" cannot name UDS-1992 files.");
  // The sampling interval as the decimal it stands for (15 significant digits).
  const double dt = *util::ParseDouble(
      util::FormatNumber((kinematics.time_s[n - 1] - kinematics.time_s[0]) / static_cast<double>(n - 1), 15));
  const double first_sample = kinematics.time_s[0] / dt;
  const long nfp = std::lround(first_sample);
  if (std::abs(first_sample - static_cast<double>(nfp)) > 1e-6)
    throw InputError(folder.string() + ": the first sample at " + util::FormatNumber(kinematics.time_s[0]) +
                     " s is not a whole number of sampling intervals (" + util::FormatNumber(dt) +
                     " s); UDS-1992 cannot place it.");

  UdsChannel templ;  // the report's "template" UDS object
  templ.number_form = form;
  templ.dimsys = "ENG";
  int number = 0;
  std::from_chars(test_number.data(), test_number.data() + test_number.size(), number);
  templ.test_number = number;  // TSTNO: the test id when numeric, else 0
  templ.test_name = test_number;
  templ.title = "napkin: head CG six-degree-of-freedom motion";
  templ.senatt = "HEAD CG";
  templ.nfp = static_cast<int>(nfp);
  templ.del_s = dt;

  std::vector<std::filesystem::path> written;
  std::filesystem::create_directories(folder);
  const char axes[3] = {'X', 'Y', 'Z'};
  auto write3 = [&](const engine::Series3& series, const std::string& prefix, const std::string& stem,
                    const char* ytyp, const char* yunits, const char* status, char frame, double scale,
                    std::optional<double> cfc, bool dcos = false) {
    const std::string file_stem = prefix + test_number + stem;  // + the axis's extension
    for (int a = 0; a < 3; ++a) {
      UdsChannel channel = templ;
      // DCOS.011, .022, .033; otherwise .00X, .00Y, .00Z.
      const std::string extension =
          dcos ? std::string(".0") + static_cast<char>('1' + a) + static_cast<char>('1' + a)
               : std::string(".00") + axes[a];
      channel.curve_name = stem + extension.substr(1);
      // DCOS axes XU, YV, ZW; otherwise XF ... (fixed) or XB ... (body).
      channel.axis = std::string(1, axes[a]) + (dcos ? static_cast<char>('U' + a) : frame);
      channel.ytyp = ytyp;
      channel.yunits = yunits;
      channel.curve_description = status;
      // FCUT is the cut-off in Hz of the last filter applied, 0 unfiltered (NHTSA doc/UDS_Vars.txt).
      channel.filter_cutoff_hz = cfc ? engine::J211CutoffOfClass(*cfc) : 0.0;
      channel.values.resize(static_cast<std::size_t>(n));
      for (Eigen::Index k = 0; k < n; ++k) channel.values[static_cast<std::size_t>(k)] = series(k, a) * scale;
      const std::filesystem::path path = folder / (file_stem + extension);
      WriteUds1992(channel, path);
      written.push_back(path);
    }
  };
  const double g_per_si = 1.0 / engine::kStandardGravity;
  const double inch_per_metre = 1.0 / engine::kMetresPerInch;
  const std::optional<double> linear = filters.linear_cfc;
  const std::optional<double> angular = filters.angular_cfc;
  write3(kinematics.acc_fixed, "F", "AM00", "ACCELERATION", "G'S", "FIXED COORDS", 'F', g_per_si, linear);
  write3(kinematics.omega_body, "B", "ROTV", "ANGULAR VELOCITY", "RADIANS/SEC", "BODY COORDS", 'B', 1.0,
         angular);
  write3(kinematics.alpha_fixed, "F", "ROTA", "ANGULAR ACCELERATION", "RADIANS/SEC**2", "FIXED COORDS", 'F',
         1.0, angular);
  write3(kinematics.dcos_rad, "F", "DCOS", "AXIS ORIENTATION", "DEGREES", "BODY TO FIXED", 'U',
         engine::kDegPerRad, angular, /*dcos=*/true);
  write3(kinematics.roll_pitch_yaw_rad, "F", "ROTD", "ANGULAR DISPLACEMENT", "DEGREES", "FIXED COORDS", 'F',
         engine::kDegPerRad, angular);
  write3(kinematics.omega_fixed, "F", "ROTV", "ANGULAR VELOCITY", "RADIANS/SEC", "FIXED COORDS", 'F', 1.0,
         angular);
  write3(kinematics.vel_fixed, "F", "VM00", "VELOCITY", "IN/SEC", "FIXED COORDS", 'F', inch_per_metre,
         linear);
  return written;
}

}  // namespace napkin::formats
