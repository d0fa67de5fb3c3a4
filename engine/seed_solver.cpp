#include "engine/seed_solver.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "common/error.h"
#include "engine/cancellation.h"
#include "engine/rotation.h"
#include "engine/units.h"

// Floating-point fidelity: this file reproduces LC_COMP (report Appendix B)
// operation by operation. REAL*4 variables are `float`, DOUBLE PRECISION
// ones (T, TDT, the TRAPINT accumulators) are `double`, and every expression
// keeps the listing's evaluation order. engine/CMakeLists.txt compiles this
// file with -ffp-contract=off so no multiply-add is fused (the reference,
// gfortran -O2 on x86-64, has none).

namespace napkin::engine {
namespace seed_detail {
namespace {

// Sense axes of the nine slots in Table 2-1 order (kNapSlots).
// One row per arm, as in the report's Table 2-1.
// clang-format off
constexpr std::array<std::array<double, 3>, 9> kNapAxes = {{
    {1, 0, 0}, {0, 1, 0}, {0, 0, 1},  // cg_x, cg_y, cg_z
    {0, 0, 1}, {1, 0, 0},             // yarm_z, yarm_x
    {0, 0, 1}, {0, 1, 0},             // xarm_z, xarm_y
    {1, 0, 0}, {0, 1, 0},             // zarm_x, zarm_y
}};
// clang-format on

// Tolerance on a unit sense axis being the Table 2-1 axis.
constexpr double kAxisTolerance = 1e-6;

// Above this many TRANS sub-steps in one sample (|omega| dt > 1000 rad) the
// body angular velocity has diverged; the listing would overflow INTEGER.
constexpr float kMaxSubSteps = 1e6f;

std::string Quoted(const std::string& s) { return "'" + s + "'"; }

// The nine NAP sensors of `array` in Table 2-1 order, validated.
std::array<const Sensor*, 9> NapSensors(const ArrayGeometry& array) {
  const std::string where = "array " + Quoted(array.name) + " cannot be processed by the seed solver";
  std::array<const Sensor*, 9> nap{};
  for (int slot = 0; slot < 9; ++slot) {
    for (const Sensor& sensor : array.sensors) {
      if (sensor.slot != kNapSlots[slot]) continue;
      if (nap[slot] != nullptr)
        throw InvalidArrayError(where + ": slot " + Quoted(sensor.slot) + " appears twice.");
      nap[slot] = &sensor;
    }
    if (nap[slot] == nullptr)
      throw InvalidArrayError(where + ": slot " + Quoted(kNapSlots[slot]) +
                              " is missing (LC_COMP needs a 3-2-2-2 array with the nine Table 2-1 slots).");
    const Sensor& sensor = *nap[slot];
    if (sensor.kind != SensorKind::kLinear)
      throw InvalidArrayError(where + ": slot " + Quoted(sensor.slot) + " must be a linear accelerometer.");
    if (!sensor.position_body_m.allFinite())
      throw InvalidArrayError(where + ": slot " + Quoted(sensor.slot) + " has a non-finite position.");
    if (!std::isfinite(sensor.si_per_unit) || sensor.si_per_unit <= 0.0)
      throw InvalidArrayError(where + ": slot " + Quoted(sensor.slot) +
                              " has no valid unit conversion factor.");
    const double axis_norm = sensor.axis_body.norm();
    const Eigen::Vector3d expected(kNapAxes[slot][0], kNapAxes[slot][1], kNapAxes[slot][2]);
    if (!std::isfinite(axis_norm) || axis_norm == 0.0 ||
        (sensor.axis_body / axis_norm - expected).norm() > kAxisTolerance)
      throw InvalidArrayError(where + ": slot " + Quoted(sensor.slot) +
                              " does not sense along its Table 2-1 axis.");
  }
  return nap;
}

Eigen::Vector3d PositionInches(const Sensor& sensor) { return sensor.position_body_m / kMetresPerInch; }

// Offset from the ideal location, computed in double and rounded once to
// REAL*4 so that e.g. 2.200 - 2.403 gives the listing's literal -.203.
Eigen::Vector3f Offset(const Sensor& sensor, const Eigen::Vector3d& ideal_in) {
  return (PositionInches(sensor) - ideal_in).cast<float>();
}

SeedGeometry GeometryOf(const ArrayGeometry& array, const std::array<const Sensor*, 9>& nap) {
  // Slot indices in kNapSlots order.
  enum { kCgX, kCgY, kCgZ, kYarmZ, kYarmX, kXarmZ, kXarmY, kZarmX, kZarmY };
  SeedGeometry g;
  // Arm lengths to the reference accelerometers of the listing's geometry
  // block: bacc6 (xarm_z), bacc4 (yarm_z), bacc8 (zarm_x).
  const double rx = PositionInches(*nap[kXarmZ]).x();
  const double ry = PositionInches(*nap[kYarmZ]).y();
  const double rz = PositionInches(*nap[kZarmX]).z();
  g.rx = static_cast<float>(rx);
  g.ry = static_cast<float>(ry);
  g.rz = static_cast<float>(rz);
  for (const auto& [arm, name] :
       {std::pair{g.rx, "x (xarm_z)"}, {g.ry, "y (yarm_z)"}, {g.rz, "z (zarm_x)"}}) {
    if (!std::isfinite(arm) || arm == 0.0f)
      throw InvalidArrayError("array " + Quoted(array.name) +
                              " cannot be processed by the seed solver: the " + name +
                              " arm length is zero.");
  }
  g.d0x = Offset(*nap[kCgX], Eigen::Vector3d::Zero());
  g.d0y = Offset(*nap[kCgY], Eigen::Vector3d::Zero());
  g.d0z = Offset(*nap[kCgZ], Eigen::Vector3d::Zero());
  g.d1y = Offset(*nap[kXarmY], Eigen::Vector3d(rx, 0, 0));
  g.d1z = Offset(*nap[kXarmZ], Eigen::Vector3d(rx, 0, 0));
  g.d2x = Offset(*nap[kYarmX], Eigen::Vector3d(0, ry, 0));
  g.d2z = Offset(*nap[kYarmZ], Eigen::Vector3d(0, ry, 0));
  g.d3x = Offset(*nap[kZarmX], Eigen::Vector3d(0, 0, rz));
  g.d3y = Offset(*nap[kZarmY], Eigen::Vector3d(0, 0, rz));
  return g;
}

// Subroutine TRANS: T <- T + (T*omeg)*delt over nstep sub-steps with omeg
// held constant, every entry clamped to [-1, 1] (listing; report eq. 2.1-5,
// 2.1-13). `t` is row-major T(i,j) = t[i][j].
void Trans(float del, float bomegx, float bomegy, float bomegz, double (&t)[3][3], Eigen::Index row) {
  float omeg[3][3];
  for (int i = 0; i < 3; ++i) omeg[i][i] = 0.0f;
  omeg[0][1] = -bomegz;
  omeg[0][2] = bomegy;
  omeg[1][2] = -bomegx;
  omeg[1][0] = -omeg[0][1];
  omeg[2][0] = -omeg[0][2];
  omeg[2][1] = -omeg[1][2];

  const float bomegv = std::sqrt(bomegx * bomegx + bomegy * bomegy + bomegz * bomegz);
  float delt = del;
  int nstep = 1;
  if (!std::isfinite(bomegv))
    throw InputError("the seed solver's body angular velocity overflowed at row " + std::to_string(row) +
                     ".");
  if (bomegv * del > 0.001f) {
    const float increments = bomegv * del / 0.001f;
    if (!(increments < kMaxSubSteps))
      throw InputError("the seed solver's body angular velocity diverged (" + std::to_string(bomegv) +
                       " rad/s) at row " + std::to_string(row) + ".");
    const int ninc = static_cast<int>(increments);  // INTEGER assignment truncates
    nstep = ninc + 1;
    delt = del / static_cast<float>(nstep);
  }

  for (int n = 0; n < nstep; ++n) {
    double tdt[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        tdt[i][j] = 0.0;
        for (int k = 0; k < 3; ++k) tdt[i][j] = tdt[i][j] + t[i][k] * static_cast<double>(omeg[k][j]);
      }
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        t[i][j] = t[i][j] + tdt[i][j] * static_cast<double>(delt);
        if (t[i][j] > 1.0) t[i][j] = 1.0;
        if (t[i][j] < -1.0) t[i][j] = -1.0;
      }
    }
  }
}

// The listing's angle extraction (labels 953/954) with the reference's
// `notrunc` clamping instead of "Results truncated".
Eigen::Vector3f ListingAnglesDeg(const double (&t)[3][3]) {
  const float rtd = 57.2958f;
  float alpha = 0.0f, beta = 0.0f, gamma = 0.0f;
  bool near_vertical = std::abs(t[2][0]) > static_cast<double>(0.9999999f);
  if (!near_vertical) {
    beta = static_cast<float>(-std::asin(t[2][0]));
    const float cosb = std::cos(beta);
    if (cosb == 0.0f) {
      near_vertical = true;
    } else {
      alpha = static_cast<float>(std::asin(std::clamp(t[2][1] / static_cast<double>(cosb), -1.0, 1.0)));
      gamma = static_cast<float>(std::asin(std::clamp(t[1][0] / static_cast<double>(cosb), -1.0, 1.0)));
    }
  }
  if (near_vertical) {  // label 953
    alpha = static_cast<float>(std::acos(t[1][1]));
    const float arg1 = 1.570796327f;
    const float arg2 = static_cast<float>(-t[2][0]);
    beta = std::copysign(arg1, arg2);  // SIGN(arg1, arg2)
    gamma = 0.0f;
  }
  return {alpha * rtd, beta * rtd, gamma * rtd};
}

// VAX ACOSD of a DOUBLE argument, stored in REAL*4.
float AcosDeg(double x) { return static_cast<float>(std::acos(x) * 57.295779513082320876798); }

// Subroutine TRAPINT for i = 1..n with z(0) = 0 (never assigned by the
// listing) and w(0) = w0: DOUBLE accumulators, REAL*4 results.
void TrapInt(const float* z, float* w, Eigen::Index n, float w0, float wfac) {
  double zm = 0.0;
  double wm = static_cast<double>(w0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double zi = static_cast<double>(z[i]);
    const double wi = wm + static_cast<double>(wfac) * (zm + zi);
    w[i] = static_cast<float>(wi);
    zm = zi;
    wm = wi;
  }
}

}  // namespace

SeedGeometry SeedGeometryOf(const ArrayGeometry& array) { return GeometryOf(array, NapSensors(array)); }

ListingTrace RunListing(const ArrayGeometry& array, const TestSignals& signals, const InitialState& initial,
                        const std::atomic<bool>* cancel) {
  const std::array<const Sensor*, 9> nap = NapSensors(array);
  const SeedGeometry geometry = GeometryOf(array, nap);
  const Eigen::Index npts = signals.size();

  const float del = static_cast<float>(signals.dt_s);
  if (!std::isfinite(signals.dt_s) || !(del > 0.0f))
    throw InputError("the sampling interval " + std::to_string(signals.dt_s) +
                     " s is not a positive number.");
  if (!initial.orientation_rad.allFinite() || !initial.velocity_fixed_mps.allFinite() ||
      !initial.omega_body_radps.allFinite())
    throw InputError("the initial state (orientation, velocity or angular velocity) is not finite.");

  // bacc(1..9): the nine channels in g as REAL*4 (the listing reads g).
  Eigen::Matrix<float, Eigen::Dynamic, 9> bacc(npts, 9);
  for (int slot = 0; slot < 9; ++slot) {
    const int column = signals.FindSlot(kNapSlots[slot]);
    if (column < 0 || column >= signals.samples.cols())
      throw InputError(std::string("the signals have no channel for slot '") + kNapSlots[slot] +
                       "' needed by the seed solver.");
    // Exactly 1 for channels recorded in g, so such samples pass unchanged.
    const double g_per_unit = nap[slot]->si_per_unit / kStandardGravity;
    for (Eigen::Index k = 0; k < npts; ++k) {
      const float value = static_cast<float>(signals.samples(k, column) * g_per_unit);
      if (!std::isfinite(value))
        throw InputError(std::string("channel '") + kNapSlots[slot] + "' row " + std::to_string(k) +
                         " is not a finite acceleration.");
      bacc(k, slot) = value;
    }
  }

  ListingTrace out;
  out.time.resize(npts);
  for (SeriesF3* series : {&out.facc_g, &out.bomeg, &out.bomegd, &out.bacc_cg_g, &out.fomegd, &out.fomeg,
                           &out.fvel_inps, &out.alpha_beta_gamma_deg, &out.ang_deg})
    series->resize(npts, 3);
  out.t_rowmajor.resize(npts, 9);

  const float gacc = 386.088f;
  const float hgacc = gacc * 0.500f;

  // Geometry block of the listing, named as there.
  const float rx = geometry.rx, ry = geometry.ry, rz = geometry.rz;
  const float d0x1 = geometry.d0x[0], d0x2 = geometry.d0x[1], d0x3 = geometry.d0x[2];
  const float d0y1 = geometry.d0y[0], d0y2 = geometry.d0y[1], d0y3 = geometry.d0y[2];
  const float d0z3 = geometry.d0z[2];
  const float d1y1 = geometry.d1y[0], d1y2 = geometry.d1y[1], d1y3 = geometry.d1y[2];
  const float d1z3 = geometry.d1z[2];
  const float d2x1 = geometry.d2x[0], d2x2 = geometry.d2x[1], d2x3 = geometry.d2x[2];
  const float d2z3 = geometry.d2z[2];
  const float d3x1 = geometry.d3x[0];
  const float d3y2 = geometry.d3y[1];

  // Compensation coefficients (Appendix A, A-6..A-11; c2 and c7 as in the
  // Errata, c1 with the listing's leading minus).
  const float a4 = -(d2z3 - d0z3) / (2.f * ry) + (d3y2 - d0y2) / (2.f * rz);
  const float a5 = -(d2z3 - d0z3) / (2.f * ry);
  const float b4 = (d1z3 - d0z3) / (2.f * rx);
  const float b5 = -(d3x1 - d0x1) / (2.f * rz) + (d1z3 - d0z3) / (2.f * rx);
  const float c1 = -(d1y3 - d0y3) / (2.f * rx);
  const float c2 = -(d2x3 - d0x3) / (2.f * ry);
  const float c3 = (d1y1 - d0y1) / (2.f * rx) + (d2x2 - d0x2) / (2.f * ry);
  const float c4 = -(d1y2 - d0y2) / (2.f * rx);
  const float c5 = (d2x1 - d0x1) / (2.f * ry);
  const float c6 = -(d1y2 - d0y2) / (2.f * rx) + (d2x1 - d0x1) / (2.f * ry);
  const float c7 = (d1y1 - d0y1) / (2.f * rx) - (d2x2 - d0x2) / (2.f * ry);
  const float c8 = -(d2x3 - d0x3) / (2.f * ry);
  const float c9 = (d1y3 - d0y3) / (2.f * rx);
  if (!(std::isfinite(1.0f + c3) && 1.0f + c3 != 0.0f))
    throw InvalidArrayError(
        "array " + Quoted(array.name) +
        " cannot be processed by the seed solver: its compensation matrix (A-11) is singular.");

  float ai[3][3];  // Ai(i,j) = ai[i-1][j-1]
  ai[0][0] = 1.0f;
  ai[1][0] = 0.0f;
  ai[2][0] = -c1 / (1.0f + c3);
  ai[0][1] = 0.0f;
  ai[1][1] = 1.0f;
  ai[2][1] = -c2 / (1.0f + c3);
  ai[0][2] = 0.0f;
  ai[1][2] = 0.0f;
  ai[2][2] = 1.0f / (1.0f + c3);

  // Initial T = Rx(phi) Ry(theta) Rz(psi), evaluated in REAL*4 and stored
  // in DOUBLE (listing; eq. 2.1-14/15).
  const float phi = static_cast<float>(initial.orientation_rad.x());
  const float theta = static_cast<float>(initial.orientation_rad.y());
  const float psi = static_cast<float>(initial.orientation_rad.z());
  double t[3][3];
  t[0][0] = +std::cos(theta) * std::cos(psi);
  t[1][0] = +std::sin(phi) * std::sin(theta) * std::cos(psi) + std::cos(phi) * std::sin(psi);
  t[2][0] = -(std::cos(phi) * std::sin(theta) * std::cos(psi)) + std::sin(phi) * std::sin(psi);
  t[0][1] = -(std::cos(theta) * std::sin(psi));
  t[1][1] = -(std::sin(phi) * std::sin(theta) * std::sin(psi)) + std::cos(phi) * std::cos(psi);
  t[2][1] = +std::cos(phi) * std::sin(theta) * std::sin(psi) + std::sin(phi) * std::cos(psi);
  t[0][2] = +std::sin(theta);
  t[1][2] = -(std::sin(phi) * std::cos(theta));
  t[2][2] = +std::cos(phi) * std::cos(theta);

  // The listing starts from rest; a non-zero initial body rate is taken as
  // the value before the first sample.
  float bomegx = static_cast<float>(initial.omega_body_radps.x());
  float bomegy = static_cast<float>(initial.omega_body_radps.y());
  float bomegz = static_cast<float>(initial.omega_body_radps.z());

  for (Eigen::Index k = 0; k < npts; ++k) {
    ThrowIfCancelled(cancel, k);
    const int i = static_cast<int>(k) + 1;  // listing sample index
    float bacc1 = bacc(k, 0), bacc2 = bacc(k, 1), bacc3 = bacc(k, 2);
    const float bacc4 = bacc(k, 3), bacc5 = bacc(k, 4), bacc6 = bacc(k, 5);
    const float bacc7 = bacc(k, 6), bacc8 = bacc(k, 7), bacc9 = bacc(k, 8);

    // Coplanar estimate (eq. 2.1-11 / A-1).
    float bomegdx = ((bacc4 - bacc3) / ry + (bacc2 - bacc9) / rz) * hgacc;
    float bomegdy = ((bacc3 - bacc6) / rx + (bacc8 - bacc1) / rz) * hgacc;
    float bomegdz = ((bacc7 - bacc2) / rx + (bacc1 - bacc5) / ry) * hgacc;

    // First-order compensation with the previous step's body rates.
    const float q1 = a4 * (bomegx * bomegx) + a5 * (bomegy * bomegy);
    const float q2 = b4 * (bomegx * bomegx) + b5 * (bomegy * bomegy);
    const float q3 = c4 * (bomegx * bomegx) + c5 * (bomegy * bomegy) + c6 * (bomegz * bomegz) +
                     c7 * bomegx * bomegy + c8 * bomegx * bomegz + c9 * bomegy * bomegz;
    const float r1 = bomegdx - q1;
    const float r2 = bomegdy - q2;
    const float r3 = bomegdz - q3;
    bomegdx = ai[0][0] * r1 + ai[0][1] * r2 + ai[0][2] * r3;
    bomegdy = ai[1][0] * r1 + ai[1][1] * r2 + ai[1][2] * r3;
    bomegdz = ai[2][0] * r1 + ai[2][1] * r2 + ai[2][2] * r3;

    // Forward Euler.
    bomegx = bomegx + bomegdx * del;
    bomegy = bomegy + bomegdy * del;
    bomegz = bomegz + bomegdz * del;

    Trans(del, bomegx, bomegy, bomegz, t, k);

    // CG centripetal correction with the updated rates.
    bacc1 = bacc1 + d0x1 * (bomegz * bomegz + bomegy * bomegy) / gacc;
    bacc2 = bacc2 + d0y2 * (bomegx * bomegx + bomegz * bomegz) / gacc;
    bacc3 = bacc3 + d0z3 * (bomegx * bomegx + bomegy * bomegy) / gacc;

    // Transforms with the updated T: DOUBLE sums stored in REAL*4.
    const auto to_fixed = [&t](int row, float x, float y, float z) {
      return static_cast<float>(t[row][0] * static_cast<double>(x) + t[row][1] * static_cast<double>(y) +
                                t[row][2] * static_cast<double>(z));
    };
    for (int row = 0; row < 3; ++row) {
      out.facc_g(k, row) = to_fixed(row, bacc1, bacc2, bacc3);
      out.fomegd(k, row) = to_fixed(row, bomegdx, bomegdy, bomegdz);
      out.fomeg(k, row) = to_fixed(row, bomegx, bomegy, bomegz);
    }
    if (!(out.facc_g.row(k).allFinite() && out.fomegd.row(k).allFinite()))
      throw InputError("the seed solver's accelerations overflowed REAL*4 at row " + std::to_string(k) + ".");
    out.time[k] = static_cast<float>(i) * del;
    out.bomeg.row(k) << bomegx, bomegy, bomegz;
    out.bomegd.row(k) << bomegdx, bomegdy, bomegdz;
    out.bacc_cg_g.row(k) << bacc1, bacc2, bacc3;
    out.alpha_beta_gamma_deg.row(k) = ListingAnglesDeg(t);
    out.ang_deg.row(k) << AcosDeg(t[0][0]), AcosDeg(t[1][1]), AcosDeg(t[2][2]);
    for (int e = 0; e < 9; ++e) out.t_rowmajor(k, e) = t[e / 3][e % 3];
  }

  // Velocities (TRAPINT with HGacc*del: in/s from g).
  const float wfac = hgacc * del;
  for (int axis = 0; axis < 3; ++axis) {
    const float inivel = static_cast<float>(initial.velocity_fixed_mps[axis] / kMetresPerInch);
    TrapInt(out.facc_g.col(axis).data(), out.fvel_inps.col(axis).data(), npts, inivel, wfac);
  }
  return out;
}

}  // namespace seed_detail

Kinematics SolveSeed(const ArrayGeometry& array, const TestSignals& signals, const InitialState& initial,
                     const std::atomic<bool>* cancel) {
  const seed_detail::ListingTrace trace = seed_detail::RunListing(array, signals, initial, cancel);
  const Eigen::Index n = trace.time.size();
  Kinematics kin;
  kin.Resize(n);
  for (Eigen::Index k = 0; k < n; ++k) kin.time_s[k] = signals.TimeAt(k);
  kin.dt_s = signals.dt_s;
  kin.omega_body = trace.bomeg.cast<double>();
  kin.alpha_body = trace.bomegd.cast<double>();
  kin.omega_fixed = trace.fomeg.cast<double>();
  kin.alpha_fixed = trace.fomegd.cast<double>();
  kin.acc_body = trace.bacc_cg_g.cast<double>() * kStandardGravity;
  kin.acc_fixed = trace.facc_g.cast<double>() * kStandardGravity;
  kin.vel_fixed = trace.fvel_inps.cast<double>() * kMetresPerInch;

  // The listing integrates no displacement: trapezoid of the velocity,
  // starting at 0 at the first sample.
  const double half_dt = 0.5 * signals.dt_s;
  for (int axis = 0; axis < 3 && n > 0; ++axis) {
    kin.pos_fixed(0, axis) = 0.0;
    for (Eigen::Index k = 1; k < n; ++k)
      kin.pos_fixed(k, axis) =
          kin.pos_fixed(k - 1, axis) + half_dt * (kin.vel_fixed(k - 1, axis) + kin.vel_fixed(k, axis));
  }

  // T is Euler-integrated and drifts off SO(3) (|T T^T - I| ~ 1e-3 after a
  // 1.5 rad rotation); the orientation outputs use its nearest rotation.
  Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
  for (Eigen::Index k = 0; k < n; ++k) {
    ThrowIfCancelled(cancel, k);
    Eigen::Matrix3d t;
    for (int e = 0; e < 9; ++e) t(e / 3, e % 3) = trace.t_rowmajor(k, e);
    const Eigen::Matrix3d fixed_from_body = NearestRotation(t);
    Eigen::Quaterniond q(fixed_from_body);
    q.normalize();
    // Keep the quaternion on the hemisphere of the previous sample so the
    // series is continuous (q and -q are the same rotation).
    if ((k == 0 && q.w() < 0.0) || (k > 0 && q.coeffs().dot(previous.coeffs()) < 0.0)) q.coeffs() *= -1.0;
    previous = q;
    kin.quat_fixed_from_body.row(k) << q.w(), q.x(), q.y(), q.z();
    kin.roll_pitch_yaw_rad.row(k) = RollPitchYaw(fixed_from_body).transpose();
    kin.dcos_rad.row(k) = DirectionCosineAngles(t).transpose();
  }
  kin.residual.setZero(n);
  return kin;
}

}  // namespace napkin::engine
