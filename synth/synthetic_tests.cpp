#include "synth/synthetic_tests.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/rotation.h"
#include "engine/units.h"

namespace napkin::synth {
namespace {

using Eigen::Index;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// Exact rigid-body state at one instant.
struct MotionState {
  Matrix3d fixed_from_body = Matrix3d::Identity();
  Vector3d omega_body = Vector3d::Zero();
  Vector3d alpha_body = Vector3d::Zero();
  Vector3d acc_fixed = Vector3d::Zero();  // CG
  Vector3d vel_fixed = Vector3d::Zero();
  Vector3d pos_fixed = Vector3d::Zero();
};

using Motion = std::function<MotionState(double t_s)>;

// Samples `motion` at t = 0, dt, ..., (n-1) dt: what each sensor of `array`
// records (rigid-body model of docs/algorithms.md, in the sensor's unit) and the
// exact kinematics.
SyntheticTest Sample(std::string name, const engine::ArrayGeometry& array, Index n,
                     const SynthOptions& options, const engine::InitialState& initial, const Motion& motion) {
  SyntheticTest test;
  test.name = std::move(name);
  test.array = array;
  engine::ValidateArray(test.array);
  test.initial = initial;
  const double dt = 1.0 / options.rate_hz;
  engine::TestSignals& signals = test.signals;
  signals.dt_s = dt;
  signals.t0_s = 0.0;
  for (const engine::Sensor& sensor : test.array.sensors) signals.slots.push_back(sensor.slot);
  signals.samples.resize(n, static_cast<Index>(test.array.sensors.size()));
  engine::Kinematics& truth = test.truth;
  truth.Resize(n);

  const Matrix3d fixed_from_body_0 = engine::InitialFixedFromBody(initial.orientation_rad);
  const Vector3d gravity_body_0 = fixed_from_body_0.transpose() * options.g_fixed_mps2;
  Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / options.rate_hz;
    const MotionState s = motion(t);
    const Matrix3d& r = s.fixed_from_body;
    const Vector3d acc_body = r.transpose() * s.acc_fixed;
    // Accelerometers sense a - g; zeroed at t = 0 (docs/algorithms.md "Gravity").
    const Vector3d gravity_reading =
        options.gravity ? Vector3d(r.transpose() * options.g_fixed_mps2 - gravity_body_0) : Vector3d::Zero();
    for (std::size_t i = 0; i < test.array.sensors.size(); ++i) {
      const engine::Sensor& sensor = test.array.sensors[i];
      double value_si;
      if (sensor.kind == engine::SensorKind::kLinear) {
        const Vector3d& p = sensor.position_body_m;
        const Vector3d point_acc =
            acc_body + s.alpha_body.cross(p) + s.omega_body.cross(s.omega_body.cross(p));
        value_si = sensor.axis_body.dot(point_acc - gravity_reading);
      } else {
        value_si = sensor.axis_body.dot(s.omega_body);
      }
      signals.samples(k, static_cast<Index>(i)) = value_si / sensor.si_per_unit;
    }
    truth.time_s(k) = t;
    truth.omega_body.row(k) = s.omega_body.transpose();
    truth.alpha_body.row(k) = s.alpha_body.transpose();
    truth.omega_fixed.row(k) = (r * s.omega_body).transpose();
    truth.alpha_fixed.row(k) = (r * s.alpha_body).transpose();
    truth.acc_body.row(k) = acc_body.transpose();
    truth.acc_fixed.row(k) = s.acc_fixed.transpose();
    truth.vel_fixed.row(k) = s.vel_fixed.transpose();
    truth.pos_fixed.row(k) = s.pos_fixed.transpose();
    Eigen::Quaterniond q(r);
    q.normalize();
    if (k > 0 && q.coeffs().dot(previous.coeffs()) < 0.0) q.coeffs() *= -1.0;  // continuous sign
    previous = q;
    truth.quat_fixed_from_body.row(k) << q.w(), q.x(), q.y(), q.z();
    truth.roll_pitch_yaw_rad.row(k) = engine::RollPitchYaw(r).transpose();
    truth.dcos_rad.row(k) = engine::DirectionCosineAngles(r).transpose();
  }
  truth.residual.setZero(n);
  return test;
}

Index SampleCount(double duration_s, double rate_hz) {
  return static_cast<Index>(std::llround(duration_s * rate_hz)) + 1;
}

// Haversine pulse of `amplitude` starting at `start_s`, lasting `duration_s`:
// f(t) = amplitude (1 - cos(2 pi u)) / 2, u = (t - start) / duration in [0, 1].
struct Pulse {
  double start_s = 0.0;
  double duration_s = 1.0;
  double amplitude = 0.0;

  // f'(t), f(t), its integral and double integral from the pulse start.
  void Evaluate(double t, double& derivative, double& value, double& integral,
                double& double_integral) const {
    const double u = (t - start_s) / duration_s;
    const double two_pi_u = 2.0 * std::numbers::pi * u;
    if (u <= 0.0) {
      derivative = value = integral = double_integral = 0.0;
    } else if (u < 1.0) {
      derivative = amplitude * std::numbers::pi * std::sin(two_pi_u) / duration_s;
      value = amplitude * 0.5 * (1.0 - std::cos(two_pi_u));
      integral = amplitude * duration_s * 0.5 * (u - std::sin(two_pi_u) / (2.0 * std::numbers::pi));
      double_integral =
          amplitude * duration_s * duration_s * 0.5 *
          (0.5 * u * u + (std::cos(two_pi_u) - 1.0) / (4.0 * std::numbers::pi * std::numbers::pi));
    } else {
      derivative = value = 0.0;
      integral = amplitude * duration_s * 0.5;
      double_integral = amplitude * duration_s * duration_s * (0.25 + 0.5 * (u - 1.0));
    }
  }
};

struct PulseSum {
  std::vector<Pulse> pulses;
  void Evaluate(double t, double& derivative, double& value, double& integral,
                double& double_integral) const {
    derivative = value = integral = double_integral = 0.0;
    for (const Pulse& pulse : pulses) {
      double d, v, i, ii;
      pulse.Evaluate(t, d, v, i, ii);
      derivative += d;
      value += v;
      integral += i;
      double_integral += ii;
    }
  }
};

// Portable uniform numbers from the standard's fully specified mt19937_64.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  double operator()() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double operator()(double lo, double hi) { return lo + (hi - lo) * (*this)(); }
  int Int(int lo, int hi) { return lo + static_cast<int>((*this)() * (hi - lo + 1)); }

 private:
  std::mt19937_64 engine_;
};

// Standard normal deviate from two uniforms (Box-Muller), portable unlike
// std::normal_distribution.
double Normal(Uniform& uniform) {
  const double u1 = 1.0 - uniform();  // in (0, 1]
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// A normal deviate truncated at +-3 (redrawn beyond).
double TruncatedNormal(Uniform& uniform) {
  for (;;) {
    const double z = Normal(uniform);
    if (std::abs(z) <= 3.0) return z;
  }
}

// 2-4 (or `min`-`max`) haversine pulses in [0, duration], scaled so that the
// largest |sum| is `peak`.
PulseSum RandomPulses(Uniform& uniform, int min_count, int max_count, double min_width_s, double max_width_s,
                      double duration_s, double peak) {
  PulseSum sum;
  const int count = uniform.Int(min_count, max_count);
  for (int i = 0; i < count; ++i) {
    Pulse pulse;
    pulse.duration_s = std::min(uniform(min_width_s, max_width_s), 0.9 * duration_s);
    pulse.start_s = uniform(0.0, duration_s - pulse.duration_s);
    pulse.amplitude = (uniform() < 0.5 ? -1.0 : 1.0) * uniform(0.4, 1.0);
    sum.pulses.push_back(pulse);
  }
  double largest = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    double d, v, in, ii;
    sum.Evaluate(duration_s * i / 4000.0, d, v, in, ii);
    largest = std::max(largest, std::abs(v));
  }
  if (largest > 0.0)
    for (Pulse& pulse : sum.pulses) pulse.amplitude *= peak / largest;
  return sum;
}

}  // namespace

SyntheticTest SynthSeedFixedAxis(const engine::ArrayGeometry& array, const Eigen::Vector3d& orientation_rad,
                                 const SynthOptions& options) {
  // Report section 4.5 (and lc_comp/gen_case.py): the head turns about an
  // axis parallel to fixed Y through A = CG0 + (0, 0, 10 in), so the CG
  // swings on a 10 in radius; R(t) = Ry(Theta(t)) R0.
  constexpr double kAmplitude = 25.0, kPulse = 0.06;
  const double arm_m = 10.0 * engine::kMetresPerInch;
  const double rate = 2.0 * std::numbers::pi / kPulse;
  const Matrix3d fixed_from_body_0 = engine::InitialFixedFromBody(orientation_rad);
  engine::InitialState initial;
  initial.orientation_rad = orientation_rad;
  const Motion motion = [=](double t) {
    double omega = 0.0, omega_rate = 0.0, angle = kAmplitude * kPulse;
    if (t <= kPulse) {
      omega = kAmplitude * (1.0 - std::cos(rate * t));
      omega_rate = kAmplitude * rate * std::sin(rate * t);
      angle = kAmplitude * (t - std::sin(rate * t) / rate);
    }
    MotionState s;
    const Matrix3d turn = engine::Ry(angle);
    s.fixed_from_body = turn * fixed_from_body_0;
    const Vector3d omega_fixed(0.0, omega, 0.0), alpha_fixed(0.0, omega_rate, 0.0);
    s.omega_body = s.fixed_from_body.transpose() * omega_fixed;
    s.alpha_body = s.fixed_from_body.transpose() * alpha_fixed;  // d/dt (R^T w) = R^T dw/dt for w || axis
    const Vector3d axis_to_cg = turn * Vector3d(0.0, 0.0, -arm_m);
    s.pos_fixed = Vector3d(0.0, 0.0, arm_m) + axis_to_cg;
    s.vel_fixed = omega_fixed.cross(axis_to_cg);
    s.acc_fixed = alpha_fixed.cross(axis_to_cg) + omega_fixed.cross(omega_fixed.cross(axis_to_cg));
    return s;
  };
  return Sample("seed-fixed-axis", array, SampleCount(0.1, options.rate_hz), options, initial, motion);
}

SyntheticTest SynthSequential(const engine::ArrayGeometry& array, const SynthOptions& options) {
  // Report section 4.4: three 90 deg turns about body x, y, z about the CG,
  // theta(t) = 45 deg (1 - cos(pi (t - start) / 40 ms)). The angular
  // acceleration jumps at the start and end of each turn; a sample exactly
  // on a jump takes the mean of the one-sided limits (what a band-limited
  // record shows there, and what makes trapezoid-type integration exact);
  // the first sample, at t = 0, takes the right-hand limit.
  constexpr double kTurn = 0.04;
  constexpr std::array<double, 3> kStarts = {0.0, 0.05, 0.10};
  const double half_angle = 0.25 * std::numbers::pi, rate = std::numbers::pi / kTurn;
  const Motion motion = [=](double t) {
    std::array<double, 3> angle{}, speed{}, accel{};
    for (int j = 0; j < 3; ++j) {
      const double tau = t - kStarts[static_cast<std::size_t>(j)];
      const double tol = 1e-9 * kTurn;
      double& a = angle[static_cast<std::size_t>(j)];
      double& w = speed[static_cast<std::size_t>(j)];
      double& al = accel[static_cast<std::size_t>(j)];
      if (tau < -tol) {
        a = w = al = 0.0;
      } else if (tau > kTurn + tol) {
        a = 2.0 * half_angle;
        w = al = 0.0;
      } else {
        a = half_angle * (1.0 - std::cos(rate * tau));
        w = half_angle * rate * std::sin(rate * tau);
        al = half_angle * rate * rate * std::cos(rate * tau);
        // On an interior jump: the mean. The record's first sample has no
        // left side; it takes the motion's right-hand limit.
        if ((std::abs(tau) <= tol && t > tol) || std::abs(tau - kTurn) <= tol) al *= 0.5;
      }
    }
    MotionState s;
    // R = Rx(a0) Ry(a1) Rz(a2): turns about body axes compose on the right.
    const Matrix3d ry = engine::Ry(angle[1]), rz = engine::Rz(angle[2]);
    s.fixed_from_body = engine::Rx(angle[0]) * ry * rz;
    const Vector3d x_in_body = (ry * rz).transpose() * Vector3d::UnitX();
    const Vector3d y_in_body = rz.transpose() * Vector3d::UnitY();
    // The turns never overlap, so products of two turn rates vanish and
    // alpha is the turn's angular acceleration about its body axis.
    s.omega_body = speed[0] * x_in_body + speed[1] * y_in_body + speed[2] * Vector3d::UnitZ();
    s.alpha_body = accel[0] * x_in_body + accel[1] * y_in_body + accel[2] * Vector3d::UnitZ();
    return s;
  };
  return Sample("seed-sequential", array, SampleCount(0.15, options.rate_hz), options, engine::InitialState{},
                motion);
}

SyntheticTest SynthRandomMotion(const engine::ArrayGeometry& array, const RandomMotionOptions& options) {
  // R(t) = R0 Rz(psi) Ry(theta) Rx(phi) with Euler-angle rates that are
  // sums of haversine pulses (so omega(0) = alpha(0) = 0); omega and alpha
  // from the ZYX Euler kinematics analytically; the CG acceleration in fixed
  // axes is a sum of haversine pulses too, with velocity and position its
  // exact integrals.
  Uniform uniform(options.seed);
  const double duration = options.duration_s;
  std::array<PulseSum, 3> euler_rates, cg_acc;
  for (PulseSum& rate : euler_rates)
    rate = RandomPulses(uniform, 2, 4, 0.015, 0.06, duration, options.peak_omega_radps * uniform(0.4, 0.75));
  for (PulseSum& acc : cg_acc)
    acc = RandomPulses(uniform, 1, 3, 0.006, 0.04, duration,
                       options.peak_acc_g * engine::kStandardGravity * uniform(0.4, 0.75));
  engine::InitialState initial;
  if (options.random_initial_orientation)
    initial.orientation_rad = Vector3d(uniform(-std::numbers::pi, std::numbers::pi),
                                       uniform(-0.45 * std::numbers::pi, 0.45 * std::numbers::pi),
                                       uniform(-std::numbers::pi, std::numbers::pi));
  if (options.random_initial_velocity)
    initial.velocity_fixed_mps = Vector3d(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(-6.0, 6.0));
  const Matrix3d fixed_from_body_0 = engine::InitialFixedFromBody(initial.orientation_rad);
  const Vector3d velocity_0 = initial.velocity_fixed_mps;

  const Motion motion = [=](double t) {
    std::array<double, 3> angle{}, rate{}, accel{};  // phi, theta, psi and derivatives
    for (std::size_t i = 0; i < 3; ++i) {
      double dummy;
      euler_rates[i].Evaluate(t, accel[i], rate[i], angle[i], dummy);
    }
    const double sf = std::sin(angle[0]), cf = std::cos(angle[0]);
    const double st = std::sin(angle[1]), ct = std::cos(angle[1]);
    const double fd = rate[0], td = rate[1], pd = rate[2];
    const double fdd = accel[0], tdd = accel[1], pdd = accel[2];
    MotionState s;
    s.fixed_from_body =
        fixed_from_body_0 * engine::Rz(angle[2]) * engine::Ry(angle[1]) * engine::Rx(angle[0]);
    // E = Rz(psi) Ry(theta) Rx(phi): E^T dE/dt = [omega_body]x with
    s.omega_body = Vector3d(fd - pd * st, td * cf + pd * ct * sf, -td * sf + pd * ct * cf);
    s.alpha_body = Vector3d(fdd - pdd * st - pd * td * ct,
                            tdd * cf - td * fd * sf + pdd * ct * sf - pd * td * st * sf + pd * fd * ct * cf,
                            -tdd * sf - td * fd * cf + pdd * ct * cf - pd * td * st * cf - pd * fd * ct * sf);
    for (int i = 0; i < 3; ++i) {
      double jerk, a, v, p;
      cg_acc[static_cast<std::size_t>(i)].Evaluate(t, jerk, a, v, p);
      s.acc_fixed(i) = a;
      s.vel_fixed(i) = velocity_0(i) + v;
      s.pos_fixed(i) = velocity_0(i) * t + p;
    }
    return s;
  };
  return Sample("random-" + std::to_string(options.seed), array, SampleCount(duration, options.synth.rate_hz),
                options.synth, initial, motion);
}

engine::ArrayGeometry DisplaceSensors(const engine::ArrayGeometry& array, double max_offset_m,
                                      std::uint64_t seed) {
  Uniform uniform(seed);
  engine::ArrayGeometry displaced = array;
  for (engine::Sensor& sensor : displaced.sensors) {
    Vector3d offset;
    do {
      offset = Vector3d(uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
    } while (offset.squaredNorm() > 1.0);  // uniform in the unit ball
    sensor.position_body_m += max_offset_m * offset;
  }
  return displaced;
}

Vector3d NominalContactPoint(double trajectory_deg) {
  constexpr double kRadius = 0.1, kRoundDeg = 6.0, kAboveDeg = 8.0;
  const double azimuth = (trajectory_deg + kRoundDeg) / engine::kDegPerRad,
               elevation = kAboveDeg / engine::kDegPerRad;
  return kRadius * Vector3d(std::cos(azimuth) * std::cos(elevation), -std::sin(azimuth) * std::cos(elevation),
                            -std::sin(elevation));
}

SyntheticTest SynthHeadImpact(const engine::ArrayGeometry& array, const HeadImpact& impact,
                              const SynthOptions& options) {
  // docs/algorithms.md "Synthetic padding series". Fixed axes = the head's
  // initial axes (the report, section 3.4: the headpart initially coincident
  // with the vehicle axes); the head flies along u and the padding pushes
  // against it: F(t) = -m A hav(t) u, with the haversine's impulse
  // A pulse / 2 = (1 + e) speed.
  const double trajectory = impact.trajectory_deg / engine::kDegPerRad;
  const Vector3d u(std::cos(trajectory), -std::sin(trajectory), 0.0);
  Pulse pulse;
  pulse.start_s = impact.contact_start_s;
  pulse.duration_s = impact.pulse_s;
  pulse.amplitude = 2.0 * (1.0 + impact.restitution) * impact.speed_mps / impact.pulse_s;  // m/s^2
  const Vector3d velocity_0 = impact.speed_mps * u;
  const Vector3d force_direction = -u;
  const double mass = impact.head_mass_kg;
  const Vector3d inertia = impact.head_inertia_kgm2;
  const Vector3d& contact = impact.contact_point_body_m;

  // Euler's equations, I dw/dt + w x I w = torque (body axes), with the
  // padding's force at the contact point and the neck's restoring torque
  // -k theta - c w (theta: the rotation vector from the initial pose).
  auto angular_acceleration = [&](double t, const Eigen::Quaterniond& q, const Vector3d& omega) {
    double jerk, acc, vel, pos;
    pulse.Evaluate(t, jerk, acc, vel, pos);
    const Vector3d force_body = q.conjugate() * (mass * acc * force_direction);
    const Vector3d torque = contact.cross(force_body) -
                            impact.neck_stiffness_nm_per_rad * engine::QuaternionLog(q) -
                            impact.neck_damping_nms_per_rad * omega;
    return Vector3d((torque - omega.cross(inertia.cwiseProduct(omega))).cwiseQuotient(inertia));
  };
  // dq/dt = q (0, w) / 2.
  auto quaternion_rate = [](const Eigen::Vector4d& q_wxyz, const Vector3d& omega) {
    const Eigen::Quaterniond q(q_wxyz(0), q_wxyz(1), q_wxyz(2), q_wxyz(3));
    const Eigen::Quaterniond rate = q * Eigen::Quaterniond(0.0, omega.x(), omega.y(), omega.z());
    return Eigen::Vector4d(0.5 * rate.w(), 0.5 * rate.x(), 0.5 * rate.y(), 0.5 * rate.z());
  };
  auto to_quaternion = [](const Eigen::Vector4d& q_wxyz) {
    return Eigen::Quaterniond(q_wxyz(0), q_wxyz(1), q_wxyz(2), q_wxyz(3)).normalized();
  };

  const Index n = SampleCount(impact.duration_s, options.rate_hz);
  constexpr int kSubSteps = 20;
  const double h = 1.0 / (options.rate_hz * kSubSteps);
  std::vector<MotionState> states(static_cast<std::size_t>(n));
  Eigen::Vector4d q(1.0, 0.0, 0.0, 0.0);
  Vector3d omega = Vector3d::Zero();
  for (Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / options.rate_hz;
    if (k > 0) {
      // Classical RK4 over the sample interval, in kSubSteps steps.
      for (int step = 0; step < kSubSteps; ++step) {
        const double t0 = static_cast<double>(k - 1) / options.rate_hz + step * h;
        const Eigen::Vector4d k1q = quaternion_rate(q, omega);
        const Vector3d k1w = angular_acceleration(t0, to_quaternion(q), omega);
        const Eigen::Vector4d q2 = q + 0.5 * h * k1q;
        const Vector3d w2 = omega + 0.5 * h * k1w;
        const Eigen::Vector4d k2q = quaternion_rate(q2, w2);
        const Vector3d k2w = angular_acceleration(t0 + 0.5 * h, to_quaternion(q2), w2);
        const Eigen::Vector4d q3 = q + 0.5 * h * k2q;
        const Vector3d w3 = omega + 0.5 * h * k2w;
        const Eigen::Vector4d k3q = quaternion_rate(q3, w3);
        const Vector3d k3w = angular_acceleration(t0 + 0.5 * h, to_quaternion(q3), w3);
        const Eigen::Vector4d q4 = q + h * k3q;
        const Vector3d w4 = omega + h * k3w;
        const Eigen::Vector4d k4q = quaternion_rate(q4, w4);
        const Vector3d k4w = angular_acceleration(t0 + h, to_quaternion(q4), w4);
        q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
        omega += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
        q.normalize();
      }
    }
    MotionState& s = states[static_cast<std::size_t>(k)];
    const Eigen::Quaterniond orientation = to_quaternion(q);
    s.fixed_from_body = orientation.toRotationMatrix();
    s.omega_body = omega;
    s.alpha_body = angular_acceleration(t, orientation, omega);
    double jerk, acc, vel, pos;
    pulse.Evaluate(t, jerk, acc, vel, pos);
    s.acc_fixed = acc * force_direction;
    s.vel_fixed = velocity_0 + vel * force_direction;
    s.pos_fixed = velocity_0 * t + pos * force_direction;
  }
  engine::InitialState initial;
  initial.velocity_fixed_mps = velocity_0;
  const double rate_hz = options.rate_hz;
  SyntheticTest test = Sample("head-impact", array, n, options, initial, [&](double t) {
    return states[static_cast<std::size_t>(std::llround(t * rate_hz))];
  });

  // Sensor noise on the signals only: the truth stays the motion's.
  Uniform uniform(impact.noise_seed ^ 0x9e3779b97f4a7c15ULL);
  for (std::size_t i = 0; i < test.array.sensors.size(); ++i) {
    const engine::Sensor& sensor = test.array.sensors[i];
    const double rms_si = sensor.kind == engine::SensorKind::kLinear
                              ? impact.noise_g * engine::kStandardGravity
                              : impact.noise_radps;
    auto column = test.signals.samples.col(static_cast<Index>(i));
    for (Index k = 0; k < n; ++k) column(k) += rms_si / sensor.si_per_unit * Normal(uniform);
  }
  return test;
}

HeadImpact ScatteredImpact(const PaddingVariant& variant, std::uint64_t seed) {
  Uniform uniform(seed);
  HeadImpact impact;
  impact.speed_mps *= 1.0 + 0.015 * TruncatedNormal(uniform);
  impact.trajectory_deg += 1.5 * TruncatedNormal(uniform);
  impact.contact_point_body_m = NominalContactPoint(impact.trajectory_deg);
  for (int axis = 0; axis < 3; ++axis) impact.contact_point_body_m(axis) += 0.002 * TruncatedNormal(uniform);
  impact.pulse_s = variant.pulse_s * (1.0 + 0.02 * TruncatedNormal(uniform));
  impact.restitution = variant.restitution;
  impact.noise_seed = seed;
  return impact;
}

const char* SynthScenarioName(SynthScenario scenario) {
  switch (scenario) {
    case SynthScenario::kSeedFixedAxis:
      return "seed-fixed-axis";
    case SynthScenario::kSeedSequential:
      return "seed-sequential";
    case SynthScenario::kRandom:
      return "random";
    case SynthScenario::kPaddingSeries:
      return "padding-series";
  }
  return "?";
}

std::optional<SynthScenario> ParseSynthScenario(std::string_view name) {
  for (const SynthScenario scenario : kSynthScenarios)
    if (name == SynthScenarioName(scenario)) return scenario;
  return std::nullopt;
}

bool HasChosenDuration(SynthScenario scenario) { return scenario == SynthScenario::kRandom; }

int DefaultCount(SynthScenario scenario) {
  return scenario == SynthScenario::kPaddingSeries ? kPaddingRepeats : 1;
}

namespace {

// "<stem>-<number>" with the number zero-padded to `width` digits.
std::string Numbered(const std::string& stem, int number, int width) {
  const std::string digits = std::to_string(number);
  const std::size_t wanted = static_cast<std::size_t>(width);
  const std::size_t padding = digits.size() < wanted ? wanted - digits.size() : 0;
  return stem + "-" + std::string(padding, '0') + digits;
}

}  // namespace

std::vector<ScenarioTest> ScenarioTests(const ScenarioOptions& options) {
  std::vector<ScenarioTest> tests;
  switch (options.scenario) {
    case SynthScenario::kSeedFixedAxis:
    case SynthScenario::kSeedSequential: {
      ScenarioTest test;
      test.external_id = options.id_prefix;
      tests.push_back(std::move(test));
      break;
    }
    case SynthScenario::kRandom: {
      const int width = std::max(4, static_cast<int>(std::to_string(options.count).size()));
      for (int i = 0; i < options.count; ++i) {
        ScenarioTest test;
        test.motion.seed = options.seed + static_cast<std::uint64_t>(i);
        test.motion.duration_s = options.duration_s;
        test.motion.synth = options.synth;
        test.seed = test.motion.seed;
        test.external_id = Numbered(options.id_prefix, i + 1, width);
        tests.push_back(std::move(test));
      }
      break;
    }
    case SynthScenario::kPaddingSeries: {
      // Every test its own impact: the scatter of a real series.
      std::uint64_t index = 0;
      for (const PaddingVariant& variant : kPaddingVariants)
        for (int r = 0; r < options.count; ++r, ++index) {
          ScenarioTest test;
          test.seed = options.seed + index;
          test.impact = ScatteredImpact(variant, *test.seed);
          test.variant = variant.name;
          test.external_id = Numbered(options.id_prefix + "-" + variant.name, r + 1, 2);
          tests.push_back(std::move(test));
        }
      break;
    }
  }
  return tests;
}

SyntheticTest SynthScenarioTest(const engine::ArrayGeometry& array, const ScenarioOptions& options,
                                const ScenarioTest& test) {
  switch (options.scenario) {
    case SynthScenario::kSeedFixedAxis:
      // Report 4.5: head initially at phi = theta = psi = 0.5 rad.
      return SynthSeedFixedAxis(array, Vector3d(0.5, 0.5, 0.5), options.synth);
    case SynthScenario::kSeedSequential:
      return SynthSequential(array, options.synth);
    case SynthScenario::kPaddingSeries: {
      SyntheticTest synthetic = SynthHeadImpact(array, test.impact.value(), options.synth);
      synthetic.name = test.external_id;
      return synthetic;
    }
    case SynthScenario::kRandom:
      break;
  }
  return SynthRandomMotion(array, test.motion);
}

}  // namespace napkin::synth
