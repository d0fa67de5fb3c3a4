// ISO/TS 18571 ratings of tests' channels (app/correlation.h;
// docs/formats.md "Correlation ratings").
#include "app/correlation.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <tuple>
#include <utility>

#include "app/report_builder.h"
#include "common/error.h"
#include "common/joined.h"
#include "engine/units.h"
#include "formats/csv.h"
#include "util/text.h"

namespace napkin::app {
namespace {

namespace fs = std::filesystem;
using formats::Dimension;

// A derived-channel name's unit suffix: its dimension and the unit per SI.
struct ChannelUnit {
  std::string_view suffix;
  Dimension dimension;
  double per_si;
  const char* quantity;  // for messages
};
constexpr ChannelUnit kChannelUnits[] = {
    {"_radps2", formats::kAngularAccelerationDimension, 1.0, "an angular acceleration"},
    {"_radps", formats::kAngularVelocityDimension, 1.0, "an angular velocity"},
    {"_mps", formats::kVelocityDimension, 1.0, "a velocity"},
    {"_g", formats::kAccelerationDimension, 1.0 / engine::kStandardGravity, "an acceleration"},
    {"_m", formats::kLengthDimension, 1.0, "a length"},
    {"_deg", formats::kAngleDimension, engine::kDegPerRad, "an angle"},
};

const ChannelUnit* UnitOfChannel(std::string_view name) {
  for (const ChannelUnit& unit : kChannelUnits)
    if (name.ends_with(unit.suffix)) return &unit;
  return nullptr;
}

const char* QuantityOf(const Dimension& dimension) {
  for (const ChannelUnit& unit : kChannelUnits)
    if (unit.dimension == dimension) return unit.quantity;
  return "a quantity of another kind";
}

constexpr const char* kResultants[] = {"acc_resultant_g", "omega_resultant_radps", "alpha_resultant_radps2"};

// "model file 'head.k'" (the name as given), for messages.
std::string ModelFile(const std::string& path) { return "model file '" + util::EscapeControl(path) + "'"; }

// What a model file holds, told by its first 64 KiB: an LS-DYNA keyword
// file (a line starting with '*'), a nodout (its block title), else a CSV.
enum class ModelFormat { kCsv, kKeyword, kNodout };
// The nodout curves whose resultant node COLUMN ("1001" or "node 1001") means for resultant
// channel `channel` (acceleration, angular velocity or angular acceleration): the node's x, y and z
// columns of that quantity ("node 1001 x-accl", ...); nullopt when the channel is not a resultant.
struct ResultantAxes {
  std::string node;
  const char* quantity;
  std::array<std::string, 3> names;
};
std::optional<ResultantAxes> NodeResultantAxes(const std::string& column, const std::string& channel) {
  const char* quantity = channel == "acc_resultant_g"          ? "accl"
                         : channel == "omega_resultant_radps"  ? "rot-vel"
                         : channel == "alpha_resultant_radps2" ? "rot-acc"
                                                               : nullptr;
  if (quantity == nullptr) return std::nullopt;
  ResultantAxes axes{column.starts_with("node ") ? column.substr(5) : column, quantity, {}};
  for (int axis = 0; axis < 3; ++axis)
    axes.names[static_cast<std::size_t>(axis)] =
        "node " + axes.node + " " + std::string(1, static_cast<char>('x' + axis)) + "-" + quantity;
  return axes;
}

// The resultant of node COLUMN for `channel` (NodeResultantAxes): the magnitude of the node's x, y
// and z columns of that quantity, on their common times. nullopt when COLUMN is no node of the
// curves or the channel is not a resultant.
std::optional<formats::ModelCurve> NodeResultant(const std::vector<formats::ModelCurve>& curves,
                                                 const std::string& column, const std::string& channel) {
  const std::optional<ResultantAxes> wanted = NodeResultantAxes(column, channel);
  if (!wanted) return std::nullopt;
  const formats::ModelCurve* axes[3] = {nullptr, nullptr, nullptr};
  for (const formats::ModelCurve& curve : curves)
    for (std::size_t axis = 0; axis < 3; ++axis)
      if (curve.name == wanted->names[axis]) axes[axis] = &curve;
  if (!axes[0] || !axes[1] || !axes[2]) return std::nullopt;
  const engine::TimeSeries& x = axes[0]->series;
  const engine::TimeSeries& y = axes[1]->series;
  const engine::TimeSeries& z = axes[2]->series;
  // The columns of one block kind share its times (formats::ReadNodout).
  if (x.time_s.size() != y.time_s.size() || x.time_s.size() != z.time_s.size()) return std::nullopt;
  formats::ModelCurve curve;
  curve.name = "node " + wanted->node + " resultant " + wanted->quantity;
  curve.dimension = axes[0]->dimension;
  curve.series.time_s = x.time_s;
  curve.series.values =
      (x.values.array().square() + y.values.array().square() + z.values.array().square()).sqrt();
  return curve;
}

ModelFormat SniffModelFormat(const formats::ModelFile& file) {
  const std::string_view head = file.head;
  if (head.find("n o d a l   p r i n t") != std::string_view::npos) return ModelFormat::kNodout;
  if (head.starts_with('*') || head.find("\n*") != std::string_view::npos) return ModelFormat::kKeyword;
  return ModelFormat::kCsv;
}

// Whether `name` (a curve's) is what `column` asks for: the name itself, or
// it without its "curve " / "node " prefix ("4" for "curve 4 head x": the
// LCID alone, "1234 x-accl" for "node 1234 x-accl").
bool CurveNamed(const std::string& name, const std::string& column) {
  if (name == column) return true;
  for (const std::string_view prefix : {"curve ", "node "}) {
    if (!name.starts_with(prefix)) continue;
    const std::string_view rest = std::string_view(name).substr(prefix.size());
    if (rest == column) return true;
    // The LCID alone names a titled curve ("curve 4 head x").
    if (prefix == "curve " && rest.starts_with(column) && rest.size() > column.size() &&
        rest[column.size()] == ' ')
      return true;
  }
  return false;
}

// 'NAME', escaped; appended, not "'" + temporary (GCC 12's false -Wrestrict, bug 105329).
std::string InSingleQuotes(const std::string& name) {
  std::string quoted = "'";
  quoted += util::EscapeControl(name);
  quoted += '\'';
  return quoted;
}

std::string CurveNames(const std::vector<std::string>& curves) {
  std::vector<std::string> names;
  for (const std::string& curve : curves) {
    if (names.size() == 12) {
      names.push_back("… (" + std::to_string(curves.size()) + " in all)");
      break;
    }
    names.push_back(InSingleQuotes(curve));
  }
  return Joined(names);
}

db::CorrelationRow RatingRecord(const TestResult& result, const RatingRow& row) {
  db::CorrelationRow record;
  record.test = result.test;
  record.config = result.config;
  record.channel = row.channel;
  record.reference = row.reference;
  record.edition = engine::NameOf(row.edition);
  record.start_s = row.start_s;
  record.end_s = row.end_s;
  record.corridor = row.rating.corridor;
  record.phase = row.rating.phase;
  record.magnitude = row.rating.magnitude;
  record.slope = row.rating.slope;
  record.overall = row.rating.overall;
  record.grade = engine::NameOf(row.rating.grade);
  record.shift_s = row.rating.shift_s;
  return record;
}

// Rates `candidate` against `reference` over the interval `options` give
// (open ends: the common span), with the edition's parameters.
RatingRow RateChannel(const std::string& test_id, const RatingOptions& options,
                      const engine::TimeSeries& reference, const engine::TimeSeries& candidate,
                      const std::string& reference_name, const std::string& candidate_name,
                      std::string shown_reference) {
  RatingRow row{test_id, options.channel, std::move(shown_reference), options.edition, 0.0, 0.0, {}};
  const auto first = [](const engine::TimeSeries& s) { return s.time_s(0); };
  const auto last = [](const engine::TimeSeries& s) { return s.time_s(s.time_s.size() - 1); };
  if (reference.time_s.size() < 2 || candidate.time_s.size() < 2)
    throw InputError((reference.time_s.size() < 2 ? reference_name : candidate_name) +
                     " has fewer than 2 samples.");
  row.start_s = options.start_s.value_or(std::max(first(reference), first(candidate)));
  row.end_s = options.end_s.value_or(std::min(last(reference), last(candidate)));
  if (!options.start_s && !options.end_s) {
    const auto span = [](const engine::TimeSeries& s) {
      return "from " + util::FormatNumber(s.time_s(0), 4) + " to " +
             util::FormatNumber(s.time_s(s.time_s.size() - 1), 4) + " s";
    };
    // Curves apart in time (a model read in the wrong --model-units): said as such, not as the
    // number of samples an empty interval holds.
    if (!(row.end_s > row.start_s))
      throw InputError(candidate_name + " runs " + span(candidate) + " and " + reference_name + " " +
                       span(reference) +
                       ": the curves do not overlap in time, so there is nothing to rate (for an LS-DYNA "
                       "model: are its --model-units right?).");
    // A short curve rated over its own few milliseconds says little about the reference's whole
    // interval: refused unless --start and --end ask for that interval.
    const double coverage = (row.end_s - row.start_s) / (last(reference) - first(reference));
    if (coverage < kMinCurveCoverage)
      throw InputError(candidate_name + " runs " + span(candidate) + ", which covers " +
                       util::FormatNumber(100.0 * coverage, 2) + " % of " + reference_name + " (" +
                       span(reference) + "), less than the " + util::FormatNumber(100.0 * kMinCurveCoverage) +
                       " % a rating over the common span needs; give --start and --end to rate that "
                       "interval anyway.");
  }
  row.rating = engine::Iso18571RateCurves(reference, candidate, {row.start_s, row.end_s},
                                          engine::Iso18571Parameters::ForEdition(options.edition),
                                          reference_name, candidate_name);
  return row;
}

std::string TestChannelName(const std::string& test_id, const std::string& channel) {
  return "test '" + test_id + "' channel " + channel;
}

// --model-units as stored: without white space, lower case ("MM, s, kg" is "mm,s,kg").
std::string CanonicalModelUnits(const std::string& units) {
  std::string canonical;
  for (const char c : units)
    if (!std::isspace(static_cast<unsigned char>(c)))
      canonical += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return canonical;
}

}  // namespace

std::vector<std::string> CorrelationChannelNames() {
  std::vector<std::string> names(std::begin(kResultants), std::end(kResultants));
  for (const std::string& column : formats::DerivedCsvColumns())
    if (UnitOfChannel(column) != nullptr) names.push_back(column);  // not time_s, not the quaternion
  return names;
}

void CheckCorrelationChannel(const std::string& channel) {
  const std::vector<std::string> names = CorrelationChannelNames();
  if (std::find(names.begin(), names.end(), channel) == names.end())
    throw UsageError("--channel '" + util::EscapeControl(channel) +
                     "' is not a derived channel; use one of " + Joined(names) + ".");
}

ChannelCurve ChannelOf(const engine::Kinematics& kinematics, const std::string& channel,
                       const std::string& test_id) {
  CheckCorrelationChannel(channel);
  const ChannelUnit& unit = *UnitOfChannel(channel);
  ChannelCurve curve{channel, unit.dimension, unit.per_si, {kinematics.time_s, {}}};
  const bool rotation = engine::HasRotation(kinematics);
  if (channel == kResultants[0]) {
    curve.series.values = kinematics.acc_body.rowwise().norm();  // the fixed frame's too
  } else if (channel == kResultants[1] || channel == kResultants[2]) {
    if (rotation)
      curve.series.values =
          (channel == kResultants[1] ? kinematics.omega_body : kinematics.alpha_body).rowwise().norm();
  } else {
    for (const formats::DerivedChannelSource& source : formats::DerivedChannelSources(kinematics)) {
      if (source.name != channel || source.values_si.empty()) continue;
      curve.series.values = Eigen::Map<const Eigen::VectorXd>(
          source.values_si.data(), static_cast<Eigen::Index>(source.values_si.size()));
      curve.display_per_si = source.to_csv_unit;
      break;
    }
  }
  if (curve.series.values.size() != curve.series.time_s.size() || !curve.series.values.allFinite())
    throw InputError("test '" + test_id + "' has no channel " + channel +
                     (rotation ? "."
                               : " (its array cannot determine the rotation, so it has only acc_body_x_g, "
                                 "acc_body_y_g, acc_body_z_g and acc_resultant_g)."));
  return curve;
}

RatingOptions ParseRatingOptions(const std::string& channel, const std::string& start, const std::string& end,
                                 const std::string& edition) {
  CheckCorrelationChannel(channel);
  RatingOptions options;
  options.channel = channel;
  const auto seconds = [](const char* option, const std::string& text) -> std::optional<double> {
    if (text.empty()) return std::nullopt;
    const std::optional<double> value = util::ParseDouble(text);
    if (!value || !std::isfinite(*value))
      throw UsageError(std::string(option) + " must be a time in seconds; it is '" +
                       util::EscapeControl(text) + "'.");
    return value;
  };
  options.start_s = seconds("--start", start);
  options.end_s = seconds("--end", end);
  if (options.start_s && options.end_s && !(*options.end_s > *options.start_s))
    throw UsageError("--end (" + end + " s) must be later than --start (" + start + " s).");
  const std::optional<engine::Iso18571Edition> parsed = engine::ParseName<engine::Iso18571Edition>(edition);
  if (!parsed)
    throw UsageError("--edition must be 2014 or 2024; it is '" + util::EscapeControl(edition) + "'.");
  options.edition = *parsed;
  return options;
}

ModelSpec ParseModelSpec(const std::string& spec) {
  // FILE:COLUMN, where FILE is the longest prefix before a ':' that is a file;
  // a spec that is a file itself has no column.
  std::error_code error;
  if (fs::is_regular_file(spec, error)) return {spec, ""};
  for (std::size_t colon = spec.rfind(':'); colon != std::string::npos && colon > 0;
       colon = spec.rfind(':', colon - 1)) {
    if (fs::is_regular_file(spec.substr(0, colon), error))
      return {spec.substr(0, colon), spec.substr(colon + 1)};
  }
  return {spec, ""};
}

void CheckModelUnitsGiven(const formats::ModelFile& file, const std::optional<std::string>& units) {
  const ModelFormat format = SniffModelFormat(file);
  if (format != ModelFormat::kCsv && !units)
    throw UsageError(ModelFile(file.path.string()) + " is an LS-DYNA " +
                     (format == ModelFormat::kNodout ? "nodout" : "keyword file") +
                     ", whose numbers carry no units; give --model-units LENGTH,TIME,MASS (e.g. mm,ms,kg or "
                     "m,s,kg).");
}

ModelReference LoadModelCurve(const std::string& spec, const ChannelCurve& channel,
                              const std::optional<std::string>& units) {
  const ModelSpec parsed = ParseModelSpec(spec);
  // Read once: the curve rated is the curve of the bytes whose hash is stored.
  return LoadModelCurve(formats::ReadModelFile(parsed.path), parsed.column, channel, units);
}

ModelReference LoadModelCurve(const formats::ModelFile& file, const std::string& column,
                              const ChannelCurve& channel, const std::optional<std::string>& units) {
  const std::string path = file.path.string();
  CheckModelUnitsGiven(file, units);
  const ModelFormat format = SniffModelFormat(file);
  if (format == ModelFormat::kCsv && units)
    throw UsageError("--model-units is for LS-DYNA files, whose numbers carry no units, but " +
                     ModelFile(path) + " is a CSV, whose header gives its units; leave --model-units out.");
  std::optional<formats::ModelUnits> model_units;
  if (units) model_units = formats::ParseModelUnits(*units, "--model-units");
  const auto read = [&](const formats::KeepCurve& keep) {
    return format == ModelFormat::kCsv       ? formats::ReadModelCsv(file, keep)
           : format == ModelFormat::kKeyword ? formats::ReadLsDynaCurves(file, *model_units, keep)
                                             : formats::ReadNodout(file, *model_units, keep);
  };
  // Only the curves that may be the one rated are kept (formats::KeepCurve), so a model of 10^7
  // points is in memory as its one curve, not as its text and every curve (issue 42, point 14):
  // the first curve named COLUMN (a second makes the choice ambiguous, said below) and for a
  // node's resultant its x, y and z; without COLUMN the first curve named like the channel and the
  // file's first curve, which is the one rated when it is the file's only one.
  const std::optional<ResultantAxes> resultant_axes = format == ModelFormat::kNodout && !column.empty()
                                                          ? NodeResultantAxes(column, channel.name)
                                                          : std::nullopt;
  bool named_kept = false, first = true;
  formats::ModelCurves curves = read([&](const std::string& name) {
    const bool is_first = std::exchange(first, false);
    if (column.empty() ? name == channel.name : CurveNamed(name, column))
      return !std::exchange(named_kept, true);
    if (!column.empty())
      return resultant_axes && std::find(resultant_axes->names.begin(), resultant_axes->names.end(), name) !=
                                   resultant_axes->names.end();
    return is_first;
  });
  // Every curve of a name asked for: more than one is ambiguous.
  const auto named = [&](const std::string& wanted, bool by_curve_named) {
    std::vector<std::string> found;
    for (const std::string& name : curves.names)
      if (by_curve_named ? CurveNamed(name, wanted) : name == wanted) found.push_back(name);
    if (found.size() > 1) {
      std::vector<std::string> quoted;
      for (const std::string& name : found) quoted.push_back(InSingleQuotes(name));
      throw InputError(ModelFile(path) + " has " + std::to_string(found.size()) + " curves named '" +
                       util::EscapeControl(wanted) + "' (" + Joined(quoted) +
                       "), so which one to rate is ambiguous; give each " +
                       (format == ModelFormat::kKeyword ? "curve its own LCID." : "column its own name."));
    }
    return found.empty() ? std::optional<std::string>() : found.front();
  };
  std::optional<std::string> chosen;             // the name of the curve rated
  std::optional<formats::ModelCurve> resultant;  // or a node's resultant, when COLUMN asks for one
  if (!column.empty()) {
    chosen = named(column, true);
    // A node alone (FILE:1001) for a resultant channel: the node's resultant, frame-free, from its
    // x, y and z columns in the model's global frame.
    if (!chosen && resultant_axes) resultant = NodeResultant(curves.kept, column, channel.name);
    if (!chosen && !resultant)
      throw InputError(ModelFile(path) + " has no curve '" + util::EscapeControl(column) +
                       "'; its curves are " + CurveNames(curves.names) + ".");
  } else if (curves.names.size() == 1) {
    chosen = curves.names.front();
  } else {
    chosen = named(channel.name, false);
    if (!chosen)
      throw InputError(ModelFile(path) + " holds " + std::to_string(curves.names.size()) +
                       " curves and none named " + channel.name + "; name one as FILE:COLUMN, one of " +
                       CurveNames(curves.names) + ".");
  }
  const auto kept = [&] {
    return std::find_if(curves.kept.begin(), curves.kept.end(),
                        [&](const formats::ModelCurve& curve) { return curve.name == *chosen; });
  };
  // The file's one curve is not its first when the columns before it are empty throughout (a
  // model CSV): read again for it alone.
  if (chosen && kept() == curves.kept.end())
    curves = read([&](const std::string& name) { return name == *chosen; });
  formats::ModelCurve curve = resultant ? std::move(*resultant) : std::move(*kept());
  curves.kept.clear();  // the other curves kept, before the chosen one is converted
  // A CSV column says its quantity by its unit; without one it is no channel's quantity (it was
  // taken for an angle, the quantity without dimension).
  if (format == ModelFormat::kCsv && !formats::ModelCsvColumnHasUnit(curve.name))
    throw InputError(ModelFile(path) + " column '" + util::EscapeControl(curve.name) +
                     "' names no unit, so its quantity is unknown; end its name in one of " +
                     formats::ModelCsvUnitSuffixes() + " (e.g. " + util::EscapeControl(curve.name) +
                     std::string(UnitOfChannel(channel.name) ? UnitOfChannel(channel.name)->suffix : "_g") +
                     ").");
  // A flat curve has no shape to rate (its phase is 1.0 for any test): refused, not graded.
  if (curve.series.values.size() > 0 && curve.series.values.maxCoeff() == curve.series.values.minCoeff())
    throw InputError(ModelFile(path) + " curve '" + util::EscapeControl(curve.name) + "' is constant (" +
                     util::FormatNumber(curve.series.values(0)) +
                     " throughout), a degenerate curve ISO/TS 18571 cannot rate.");
  if (curve.dimension && *curve.dimension != channel.dimension)
    throw InputError(ModelFile(path) + " curve '" + util::EscapeControl(curve.name) + "' is " +
                     QuantityOf(*curve.dimension) + ", but channel " + channel.name + " is " +
                     QuantityOf(channel.dimension) + ".");
  if (!curve.dimension) curve = formats::ToSi(std::move(curve), channel.dimension, *model_units);
  // A keyword file or a nodout is read in the units given; a CSV's header gives its own.
  std::optional<std::string> units_used;
  if (format != ModelFormat::kCsv && units) units_used = CanonicalModelUnits(*units);
  return {file.path.filename().string(), file.sha256, curve.name, std::move(curve.series), units_used};
}

RatingRow RateAgainstModel(db::Catalogue& catalogue, const std::string& test_id,
                           const std::string& model_spec, const std::optional<std::string>& model_units,
                           const RatingOptions& options, const ResultChoice& choice) {
  CheckCorrelationChannel(options.channel);
  const TestResult result = ResultOf(catalogue, test_id, choice);
  const ChannelCurve channel =
      ChannelOf(ReadResultKinematics(catalogue, result.test, result.config), options.channel, test_id);
  const ModelReference model = LoadModelCurve(model_spec, channel, model_units);
  const std::string shown = model.file_name + ":" + model.column;
  // A sentence about the curve's times says the units they were read in: wrong --model-units are
  // the usual reason a model's curve misses the test's interval (issue 42, point 14).
  const std::string read_in = model.units ? " (read in --model-units " + *model.units + ")" : "";
  RatingRow row = RateChannel(
      test_id, options, channel.series, model.series, TestChannelName(test_id, options.channel),
      ModelFile(ParseModelSpec(model_spec).path) + " curve '" + model.column + "'" + read_in, shown);
  db::CorrelationRow record = RatingRecord(result, row);
  record.reference_kind = "model";
  record.reference_key = "model:" + model.sha256 + ":" + model.column;
  // The units are part of what the rating rated: the same curve under other units is another rating.
  if (model.units) {
    record.model_units = model.units;
    record.reference_key += ":units=" + *model.units;
  }
  record.model_file = model.file_name;
  record.model_sha256 = model.sha256;
  record.model_column = model.column;
  catalogue.WriteCorrelation(record);
  return row;
}

RatingRow RateAgainstTest(db::Catalogue& catalogue, const std::string& test_id,
                          const std::string& reference_test_id, const RatingOptions& options,
                          const ResultChoice& choice) {
  CheckCorrelationChannel(options.channel);
  const TestResult result = ResultOf(catalogue, test_id, choice);
  const TestResult other = ResultOf(catalogue, reference_test_id, Latest{});
  const ChannelCurve rated =
      ChannelOf(ReadResultKinematics(catalogue, result.test, result.config), options.channel, test_id);
  const ChannelCurve reference = ChannelOf(ReadResultKinematics(catalogue, other.test, other.config),
                                           options.channel, reference_test_id);
  // The test named --reference-test is the reference curve, --test's the candidate judged against
  // it (ISO/TS 18571): corridor, magnitude and slope are not symmetric, and the stored row's
  // `reference` names that test.
  RatingRow row = RateChannel(test_id, options, reference.series, rated.series,
                              TestChannelName(reference_test_id, options.channel),
                              TestChannelName(test_id, options.channel), reference_test_id);
  db::CorrelationRow record = RatingRecord(result, row);
  record.reference_kind = "test";
  record.reference_key = "test:" + reference_test_id;
  record.reference_test = other.test;
  catalogue.WriteCorrelation(record);
  return row;
}

std::vector<RatingRow> RateVariantRepeats(db::Catalogue& catalogue, const std::string& series,
                                          const std::string& variant, const RatingOptions& options,
                                          bool store) {
  CheckCorrelationChannel(options.channel);
  db::TestFilter filter;
  filter.series = {series};
  filter.variants = {variant};
  struct Repeat {
    std::string test_id;
    TestResult result;
    engine::TimeSeries curve;
  };
  std::vector<Repeat> repeats;
  for (const db::LabelledResult& labelled : catalogue.ReadResults(filter, db::ResultSelection::kLatest)) {
    const std::optional<db::TestId> key = catalogue.FindTestByExternalId(labelled.test_id);
    if (!key) continue;
    const ChannelCurve channel = ChannelOf(ReadResultKinematics(catalogue, *key, labelled.config_id),
                                           options.channel, labelled.test_id);
    repeats.push_back({labelled.test_id, {*key, labelled.config_id}, channel.series});
  }
  if (repeats.size() < 2)
    throw InputError(
        "variant '" + variant + "' of series '" + series + "' has " + std::to_string(repeats.size()) +
        (repeats.size() == 1 ? " test" : " tests") +
        " with results; its repeatability needs at least 2 (run `napkin run`, or check the names "
        "with `napkin query tests`).");

  // The mean curve on the overlays' common time base, where every repeat has a sample.
  std::vector<engine::TimeSeries> curves;
  for (const Repeat& repeat : repeats) curves.push_back(repeat.curve);
  const Eigen::VectorXd base = engine::CommonTimeBase(curves, kOverlayBasePoints);
  Eigen::MatrixXd columns(base.size(), static_cast<Eigen::Index>(repeats.size()));
  for (std::size_t r = 0; r < repeats.size(); ++r)
    columns.col(static_cast<Eigen::Index>(r)) = engine::ResampleOnto(repeats[r].curve, base);
  Eigen::Index first = 0, last = base.size() - 1;
  const auto complete = [&](Eigen::Index row) { return columns.row(row).allFinite(); };
  while (first < base.size() && !complete(first)) ++first;
  while (last > first && !complete(last)) --last;
  if (last - first < 1)
    throw InputError("the tests of variant '" + variant + "' of series '" + series +
                     "' share no stretch of time on which to average channel " + options.channel + ".");
  const Eigen::Index rows = last - first + 1;
  const engine::TimeSeries mean{base.segment(first, rows), columns.middleRows(first, rows).rowwise().mean()};

  const std::string shown = "mean of " + variant;
  std::vector<RatingRow> ratings;
  for (const Repeat& repeat : repeats) {
    RatingRow row = RateChannel(repeat.test_id, options, mean, repeat.curve,
                                "the mean curve of variant '" + variant + "' of series '" + series + "'",
                                TestChannelName(repeat.test_id, options.channel), shown);
    if (store) {
      db::CorrelationRow record = RatingRecord(repeat.result, row);
      record.reference_kind = "variant-mean";
      record.reference_key = "variant-mean:" + series + "/" + variant;
      record.reference_series = series;
      record.reference_variant = variant;
      catalogue.WriteCorrelation(record);
    }
    ratings.push_back(std::move(row));
  }
  std::stable_sort(ratings.begin(), ratings.end(), [](const RatingRow& a, const RatingRow& b) {
    return std::tie(a.rating.overall, a.test_id) < std::tie(b.rating.overall, b.test_id);
  });
  return ratings;
}

db::Table RatingTable(const std::vector<RatingRow>& rows) {
  db::Table table;
  table.columns = {"test_id", "channel",   "reference", "edition", "start_s", "end_s",  "corridor",
                   "phase",   "magnitude", "slope",     "overall", "grade",   "shift_s"};
  for (const RatingRow& row : rows) {
    const engine::Iso18571Rating& r = row.rating;
    table.rows.push_back({row.test_id, row.channel, row.reference, std::string(engine::NameOf(row.edition)),
                          row.start_s, row.end_s, r.corridor, r.phase, r.magnitude, r.slope, r.overall,
                          std::string(engine::NameOf(r.grade)), r.shift_s});
  }
  return table;
}

RatingPlot PlotRating(const ChannelCurve& test, const engine::TimeSeries& model, double start_s, double end_s,
                      engine::Iso18571Edition edition, const std::string& test_name,
                      const std::string& model_name) {
  const engine::Iso18571Parameters parameters = engine::Iso18571Parameters::ForEdition(edition);
  RatingPlot plot;
  plot.rating =
      engine::Iso18571RateCurves(test.series, model, {start_s, end_s}, parameters, test_name, model_name);
  plot.time_s = engine::Iso18571TimeBase(start_s, end_s, parameters.rate_hz);
  plot.test = engine::ResampleOnto(test.series, plot.time_s) * test.display_per_si;
  plot.model = engine::ResampleOnto(model, plot.time_s) * test.display_per_si;
  plot.inner_half_width = plot.rating.inner_half_width * test.display_per_si;
  plot.outer_half_width = plot.rating.outer_half_width * test.display_per_si;
  return plot;
}

}  // namespace napkin::app
