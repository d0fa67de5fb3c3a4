// The criteria and filters of the engine on numpy arrays: napkin.hic,
// napkin.cfc, napkin.bric, the injury-risk curves and napkin.iso18571
// (docs/python.md).
#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include "common/error.h"
#include "engine/cfc_filter.h"
#include "engine/criteria.h"
#include "engine/iso18571.h"
#include "engine/processing.h"
#include "engine/summary_fields.h"
#include "python/py_bindings.h"

namespace napkin::python {
namespace {

Eigen::Map<const Eigen::VectorXd> Samples(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& values, const std::string& what) {
  if (values.ndim() != 1)
    throw InputError(what + " has " + std::to_string(values.ndim()) +
                     " dimensions; it is a 1-D array of samples.");
  return {values.data(), static_cast<Eigen::Index>(values.shape(0))};
}

// engine::Hic: the exact maximum over windows up to max_window_s (None: no
// limit), times in s from the first sample.
py::tuple Hic(const py::handle& resultant_g, double dt_s, const std::optional<double>& max_window_s,
              bool from_time_zero, double t0_s) {
  const auto values = AsFloatArray(resultant_g, "napkin.hic: resultant_g");
  const Eigen::Map<const Eigen::VectorXd> samples = Samples(values, "napkin.hic: resultant_g");
  engine::HicOptions options;
  options.window_s = max_window_s.value_or(engine::kUnlimitedHicWindow);
  options.from_time_zero = from_time_zero;
  engine::HicWindow window;
  {
    const py::gil_scoped_release computing;
    window = engine::Hic(samples, dt_s, t0_s, options);
  }
  return py::make_tuple(window.value, window.t1_s, window.t2_s);
}

// engine::CfcFilterInPlace on a copy: the two-pass SAE J211 (or ISO 6487) filter.
py::array_t<double> Cfc(const py::handle& x, double dt_s, double cfc_hz, const std::string& variant_name) {
  const std::optional<engine::CfcVariant> variant = engine::ParseName<engine::CfcVariant>(variant_name);
  if (!variant)
    throw InputError("napkin.cfc: variant \"" + variant_name + "\" is neither \"sae\" nor \"iso\".");
  if (!(std::isfinite(dt_s) && dt_s > 0.0))
    throw InputError("napkin.cfc: dt_s " + std::to_string(dt_s) +
                     " s is not a finite positive sampling interval.");
  if (!(std::isfinite(cfc_hz) && cfc_hz > 0.0))
    throw InputError("napkin.cfc: cfc " + std::to_string(cfc_hz) +
                     " Hz is not a positive channel frequency class.");
  const auto values = AsFloatArray(x, "napkin.cfc: x");
  Eigen::VectorXd filtered = Samples(values, "napkin.cfc: x");
  for (Eigen::Index k = 0; k < filtered.size(); ++k)
    if (!std::isfinite(filtered[k]))
      throw InputError("napkin.cfc: x[" + std::to_string(k) + "] is not a finite number.");
  {
    const py::gil_scoped_release computing;
    engine::CfcFilterInPlace(filtered, dt_s, cfc_hz, *variant);
  }
  return ToNumpy(std::move(filtered));
}

// engine::Bric over omega_body (samples x 3, rad/s).
double Bric(const py::handle& omega_body_radps, const std::optional<std::vector<double>>& critical) {
  const auto values = AsFloatArray(omega_body_radps, "napkin.bric: omega_body_radps");
  if (values.ndim() != 2 || values.shape(1) != 3)
    throw InputError("napkin.bric: omega_body_radps is an array of " + std::to_string(values.ndim()) +
                     " dimensions; it has one row per sample and 3 columns (x, y, z).");
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  const engine::Series3 omega = Eigen::Map<const Rows>(values.data(), values.shape(0), 3);
  Eigen::Vector3d critical_radps = engine::BricConfig{}.critical_radps;
  if (critical) {
    if (critical->size() != 3)
      throw InputError("napkin.bric: critical_radps takes 3 numbers (x, y, z), not " +
                       std::to_string(critical->size()) + ".");
    critical_radps = {(*critical)[0], (*critical)[1], (*critical)[2]};
  }
  return engine::Bric(omega, critical_radps);
}

// engine::Iso18571RateCurves on two arrays sampled every dt_s from t = 0,
// over [start_s, end_s] (None: the arrays' common span), rated at their own
// sampling: (corridor, phase, magnitude, slope, overall, grade, shift_s).
py::tuple Iso18571(const py::handle& reference, const py::handle& candidate, double dt_s,
                   const std::optional<double>& start_s, const std::optional<double>& end_s,
                   const std::string& edition_name) {
  const std::optional<engine::Iso18571Edition> edition =
      engine::ParseName<engine::Iso18571Edition>(edition_name);
  if (!edition)
    throw InputError("napkin.iso18571: edition \"" + edition_name + "\" is neither \"2014\" nor \"2024\".");
  if (!(std::isfinite(dt_s) && dt_s > 0.0))
    throw InputError("napkin.iso18571: dt_s " + std::to_string(dt_s) +
                     " s is not a finite positive sampling interval.");
  auto series = [&](const py::handle& values, const std::string& what) {
    const auto array = AsFloatArray(values, what);
    const Eigen::Map<const Eigen::VectorXd> samples = Samples(array, what);
    engine::TimeSeries s{Eigen::VectorXd(samples.size()), samples};
    for (Eigen::Index k = 0; k < samples.size(); ++k) s.time_s(k) = static_cast<double>(k) * dt_s;
    return s;
  };
  const engine::TimeSeries t = series(reference, "napkin.iso18571: reference");
  const engine::TimeSeries c = series(candidate, "napkin.iso18571: candidate");
  engine::Iso18571Parameters parameters = engine::Iso18571Parameters::ForEdition(*edition);
  parameters.rate_hz = 1.0 / dt_s;
  engine::Iso18571Rating r;
  {
    const py::gil_scoped_release computing;
    r = engine::Iso18571RateCurves(t, c, {start_s, end_s}, parameters, "napkin.iso18571: reference",
                                   "napkin.iso18571: candidate");
  }
  return py::make_tuple(r.corridor, r.phase, r.magnitude, r.slope, r.overall, engine::NameOf(r.grade),
                        r.shift_s);
}

}  // namespace

void RegisterCriteria(py::module_& module) {
  // Arguments are taken as Python objects and converted here, so that one of
  // the wrong type is a TypeError naming it (py_bindings.h AsReal, ...).
  module.def(
      "hic",
      [](const py::handle& resultant_g, const py::handle& dt, const py::handle& max_window_s,
         const py::handle& from_time_zero, const py::handle& t0_s) {
        return Translated("", [&] {
          if (!py::isinstance<py::bool_>(from_time_zero))
            throw py::type_error("napkin.hic: from_time_zero is " + Described(from_time_zero) +
                                 ", not True or False.");
          return Hic(
              resultant_g, AsReal(dt, "napkin.hic: dt_s", "the sampling interval in s"),
              AsOptionalReal(max_window_s, "napkin.hic: max_window_s", "the longest window in s, or None"),
              from_time_zero.cast<bool>(), AsReal(t0_s, "napkin.hic: t0_s", "the first sample's time in s"));
        });
      },
      py::arg("resultant_g"), py::arg("dt_s"), py::arg("max_window_s") = engine::kHic15Window,
      py::arg("from_time_zero") = false, py::arg("t0_s") = 0.0,
      "HIC of a resultant acceleration (g) sampled every dt_s s: (hic, t1_s, t2_s), the exact maximum over "
      "windows "
      "up to max_window_s (None: no limit), times in s from the first sample (plus t0_s).");
  module.def(
      "cfc",
      [](const py::handle& x, const py::handle& dt, const py::handle& cfc, const py::handle& variant) {
        return Translated("", [&] {
          return Cfc(x, AsReal(dt, "napkin.cfc: dt_s", "the sampling interval in s"),
                     AsReal(cfc, "napkin.cfc: cfc", "the channel frequency class"),
                     AsText(variant, "napkin.cfc: variant", "\"sae\" or \"iso\""));
        });
      },
      py::arg("x"), py::arg("dt_s"), py::arg("cfc") = engine::kCfc1000, py::arg("variant") = "sae",
      "x filtered by the two-pass channel frequency class filter of SAE J211 (variant 'sae') or ISO 6487 "
      "('iso').");
  module.def(
      "bric",
      [](const py::handle& omega, const py::handle& critical) {
        return Translated("", [&] {
          std::optional<std::vector<double>> critical_radps;
          if (!critical.is_none())
            critical_radps = AsReals(critical, "napkin.bric: critical_radps", "3 critical values in rad/s");
          return Bric(omega, critical_radps);
        });
      },
      py::arg("omega_body_radps"), py::arg("critical_radps") = py::none(),
      "BrIC (Takhounts 2013) of body angular velocity (samples x 3, rad/s); critical values default to "
      "66.25, 56.45, 42.87 rad/s.");
  module.def(
      "_iso18571",
      [](const py::handle& reference, const py::handle& candidate, const py::handle& dt_s,
         const py::handle& start_s, const py::handle& end_s, const py::handle& edition) {
        return Translated("", [&] {
          return Iso18571(
              reference, candidate, AsReal(dt_s, "napkin.iso18571: dt_s", "the sampling interval in s"),
              AsOptionalReal(start_s, "napkin.iso18571: start_s", "the interval's start in s, or None"),
              AsOptionalReal(end_s, "napkin.iso18571: end_s", "the interval's end in s, or None"),
              AsText(edition, "napkin.iso18571: edition", "\"2014\" or \"2024\""));
        });
      },
      py::arg("reference"), py::arg("candidate"), py::arg("dt_s"), py::arg("start_s") = py::none(),
      py::arg("end_s") = py::none(), py::arg("edition") = "2024",
      "ISO/TS 18571 rating as a plain tuple; napkin.iso18571 wraps it in a named tuple.");
  // The defaults of napkin.hic and napkin.cfc (napkin/__init__.py).
  module.attr("_HIC15_WINDOW_S") = engine::kHic15Window;
  module.attr("_CFC1000") = engine::kCfc1000;
  // One function per risk of the summary-field table, named as its field.
  for (const engine::SummaryField* field : engine::RiskFields()) {
    const engine::RiskCurve& curve = *field->curve;
    const std::string doc = engine::FieldTableLabel(*field) + " (docs/algorithms.md \"Injury risk\"); " +
                            "element-wise on arrays.";
    const std::string what = std::string("napkin.") + field->name + ": " + curve.criterion;
    module.def(
        field->name,
        [risk = curve.risk, what](const py::handle& values) -> py::object {
          return Translated("", [&]() -> py::object {
            // A number gives a float; anything else is an array of them, whose shape the result keeps.
            if (py::isinstance<py::str>(values) ||
                (!py::isinstance<py::array>(values) && !py::isinstance<py::sequence>(values)))
              return py::float_(risk(AsReal(values, what)));
            const auto array = AsFloatArray(values, what);
            py::array_t<double> result(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()));
            const double* in = array.data();
            double* out = result.mutable_data();
            for (py::ssize_t k = 0; k < array.size(); ++k) out[k] = risk(in[k]);
            if (array.ndim() == 0) return py::float_(out[0]);
            return result;
          });
        },
        py::arg(curve.criterion), doc.c_str());
  }
  // The summary-field table (engine/summary_fields.h): name, group, label,
  // unit, meaning, and for a risk its criterion, AIS level and source.
  module.def(
      "_summary_fields",
      [] {
        py::list fields;
        for (const engine::SummaryField& field : engine::SummaryFields()) {
          const char* group = field.group == engine::SummaryGroup::kHic        ? "hic"
                              : field.group == engine::SummaryGroup::kRotation ? "rotation"
                              : field.group == engine::SummaryGroup::kRisk     ? "risk"
                                                                               : "quality";
          const engine::RiskCurve* curve = field.curve;
          fields.append(py::make_tuple(field.name, group, engine::FieldLabel(field), field.unit,
                                       field.meaning,
                                       curve ? py::object(py::str(curve->criterion)) : py::object(py::none()),
                                       curve ? py::object(py::int_(curve->ais)) : py::object(py::none()),
                                       curve ? py::object(py::str(curve->source)) : py::object(py::none())));
        }
        return fields;
      },
      "The summary fields as tuples (name, group, label, unit, meaning, criterion, ais, source).");
}

}  // namespace napkin::python
