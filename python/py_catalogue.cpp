// napkin.Catalogue: a catalogue opened read-only, its queries and its
// comparisons as typed columns (app::RunQuery's and app::ComparisonTable's
// rows: numbers as float64 arrays, text as str), a test's channels as numpy
// arrays and its exports as the command writes them (docs/python.md
// "Catalogue"). Writing the catalogue stays with the CLI.
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <utility>
#include <variant>
#include <vector>

#include "app/comparison.h"
#include "app/db_protection.h"
#include "app/export.h"
#include "app/query.h"
#include "app/request_options.h"
#include "app/result_selection.h"
#include "app/table_output.h"
#include "common/error.h"
#include "db/query_kinds.h"
#include "formats/csv.h"
#include "python/py_bindings.h"
#include "records/test_inputs.h"

namespace napkin::python {
namespace {

// Whether column `c` of `table` holds text in some row (SQLite's columns are
// not typed: a numeric column of an odd catalogue might).
bool HoldsText(const db::Table& table, std::size_t c) {
  return std::any_of(table.rows.begin(), table.rows.end(), [c](const std::vector<db::Cell>& row) {
    return std::holds_alternative<std::string>(row[c]);
  });
}

// Column `c` of `table` as float64: NULL is NaN.
py::array_t<double> NumericColumn(const db::Table& table, std::size_t c) {
  Eigen::VectorXd column(static_cast<Eigen::Index>(table.rows.size()));
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const db::Cell& cell = table.rows[r][c];
    const auto k = static_cast<Eigen::Index>(r);
    if (const auto* value = std::get_if<double>(&cell))
      column[k] = *value;
    else if (const auto* whole = std::get_if<std::int64_t>(&cell))
      column[k] = static_cast<double>(*whole);
    else
      column[k] = std::numeric_limits<double>::quiet_NaN();
  }
  return ToNumpy(std::move(column));
}

// Column `c` of `table` as a list of Python values: None for NULL; text that
// an older napkin stored may not be UTF-8 (docs/formats.md "Text encoding"):
// its bad bytes become U+FFFD, as in the CLI's JSON.
py::list CellColumn(const db::Table& table, std::size_t c) {
  py::list column;
  for (const std::vector<db::Cell>& row : table.rows) {
    const db::Cell& cell = row[c];
    if (const auto* text = std::get_if<std::string>(&cell)) {
      PyObject* decoded =
          PyUnicode_DecodeUTF8(text->data(), static_cast<Py_ssize_t>(text->size()), "replace");
      if (decoded == nullptr) throw py::error_already_set();
      column.append(py::reinterpret_steal<py::object>(decoded));
    } else if (const auto* value = std::get_if<double>(&cell)) {
      column.append(py::float_(*value));
    } else if (const auto* whole = std::get_if<std::int64_t>(&cell)) {
      column.append(py::int_(*whole));
    } else {
      column.append(py::none());
    }
  }
  return column;
}

// (column names, one value per column): NumericColumn for the columns in
// `numeric` that hold no text, else CellColumn.
py::tuple TypedColumns(const db::Table& table, const std::set<std::string>& numeric) {
  py::list columns, values;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    columns.append(table.columns[c]);
    if (numeric.contains(table.columns[c]) && !HoldsText(table, c))
      values.append(NumericColumn(table, c));
    else
      values.append(CellColumn(table, c));
  }
  return py::make_tuple(columns, values);
}

class ReadOnlyCatalogue {
 public:
  explicit ReadOnlyCatalogue(std::string path) : path_(std::move(path)), catalogue_(Open(path_)) {}

  const std::string& path() const { return path_; }
  bool closed() const { return !catalogue_; }

  // Closes the database connection (again: nothing); any use after it
  // raises napkin.CatalogueError.
  void Close() { catalogue_.reset(); }

  // The rows of `napkin query KIND` as typed columns: (column names, one
  // value per column): a float64 numpy array for a numeric column (NaN where
  // the cell is NULL), else a list of str (or the number a metadata field
  // holds), None where the cell is NULL.
  py::tuple Query(const app::Query& query) {
    db::Catalogue& catalogue = Opened();
    const app::PreparedQuery prepared = app::PrepareQuery(query);
    const db::Table table = app::RunQuery(catalogue, prepared);
    std::set<std::string> numeric;
    if (prepared.limits)  // `query limits`' number columns (app/limits.h LimitsTable)
      numeric = {"value", "limit", "margin_pct", "higher_limit", "points", "max_points"};
    else
      for (const db::QueryField& field : db::QueryFields(prepared.kind))
        if (field.numeric) numeric.insert(field.name);
    return TypedColumns(table, numeric);
  }

  // The rows of `napkin compare --format json` (app::ComparisonTable) as
  // columns: with `typed` each numeric column a float64 array (NaN where
  // undefined), else every column a list of the cells (int, float, str, None).
  py::tuple Compare(const app::CompareRequest& request, bool typed) {
    const db::Table table = app::ComparisonTable(app::BuildComparison(Opened(), request));
    std::set<std::string> numeric;
    if (typed)
      for (const std::string& column : table.columns)
        if (!app::IsComparisonTextColumn(column)) numeric.insert(column);
    return TypedColumns(table, numeric);
  }

  // The derived channels of the test's result under the stored config
  // `config` (NAME or HASH-PREFIX; default: its latest result), as `napkin
  // export --format csv` writes them; or (derived false) its raw channels.
  py::dict Channels(const std::string& test_id, bool derived, const std::optional<std::string>& config) {
    if (derived) {
      // config= names a stored config (app/result_selection.h "Stored").
      const app::TestResult result = config ? app::ResultOf(Opened(), test_id, app::Stored{*config})
                                            : app::ResultOf(Opened(), test_id, app::Latest{});
      return DerivedChannelsToNumpy(app::ReadResultKinematics(Opened(), result.test, result.config));
    }
    py::dict inputs = TestInputs(test_id);
    const auto channels = inputs["channels"].cast<py::dict>();
    py::dict raw;
    raw["time_s"] = inputs["time_s"];
    for (const auto& [slot, values] : channels) raw[slot] = values;
    return raw;
  }

  // `napkin export`: the request's format written to `out` (a file, or a
  // folder for a folder format), by the command's writer. The catalogue is
  // never an output (app/db_protection.h).
  void Export(const app::ExportRequest& request, const std::string& out, bool replace_existing) {
    db::Catalogue& catalogue = Opened();
    // Once per catalogue: the protection lasts for the process (util/output_destination.h).
    if (!protected_from_output_) {
      app::ProtectCatalogueFromOutput(path_);
      protected_from_output_ = true;
    }
    app::Export(catalogue, request, out, replace_existing);
  }

  // What `napkin run` computes the test's result from, as napkin.transform's
  // keyword arguments (napkin/__init__.py Catalogue.test_inputs).
  py::dict TestInputs(const std::string& test_id) {
    const std::optional<db::TestId> test = Opened().FindTestByExternalId(test_id);
    if (!test) throw NotFoundError("test '" + test_id + "' is not in catalogue '" + path_ + "'.");
    return TestInputs(*test);
  }

 private:
  py::dict TestInputs(db::TestId test) {
    records::TestInputReader reader(Opened());
    records::TestInputs inputs = reader.Read(test);
    if (!inputs.array) throw InputError(inputs.array_error);
    const engine::TestSignals& signals = inputs.signals;
    Eigen::VectorXd time(signals.size());
    for (Eigen::Index k = 0; k < signals.size(); ++k) time[k] = signals.TimeAt(k);
    py::dict channels;
    for (std::size_t c = 0; c < signals.slots.size(); ++c)
      channels[py::str(signals.slots[c])] = ToNumpy(signals.samples.col(static_cast<Eigen::Index>(c)));
    auto triple = [](const Eigen::Vector3d& v) { return py::make_tuple(v.x(), v.y(), v.z()); };
    py::dict result;
    result["test_id"] = inputs.external_id;
    // The stored definition itself, not its name: a name may be a preset's
    // while the geometry is an edited copy (issue 29 point 6).
    // It was read already (records::ReadTestInputs), so it parses.
    result["array"] = ToPython(nlohmann::ordered_json::parse(inputs.array_record->definition_json));
    result["time_s"] = ToNumpy(std::move(time));
    result["channels"] = channels;
    result["orientation_rad"] = triple(inputs.initial.orientation_rad);
    result["initial_velocity_mps"] = triple(inputs.initial.velocity_fixed_mps);
    result["initial_omega_body_radps"] = triple(inputs.initial.omega_body_radps);
    return result;
  }

  static db::Catalogue Open(const std::string& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
      throw NotFoundError("catalogue '" + path + "' does not exist (or is not a file); `napkin init --db " +
                          path + "` creates one.");
    db::CatalogueOptions options;
    options.read_only = true;
    try {
      return db::Catalogue::Open(path, options);
    } catch (const InputError& error) {
      // A file that is not a napkin catalogue (not SQLite, another
      // application's, a newer schema): a catalogue problem, with the sentence
      // the CLI prints.
      RaiseCatalogueError(error.what());
    }
  }

  // The open catalogue; napkin.CatalogueError once closed.
  db::Catalogue& Opened() {
    if (!catalogue_)
      RaiseCatalogueError("catalogue '" + path_ +
                          "' is closed; open it again with napkin.Catalogue(path) to read from it.");
    return *catalogue_;
  }

  std::string path_;
  std::optional<db::Catalogue> catalogue_;
  bool protected_from_output_ = false;
};

std::vector<std::string> AsList(const std::optional<std::vector<std::string>>& values) {
  return values ? *values : std::vector<std::string>{};
}

}  // namespace

void RegisterCatalogue(py::module_& module) {
  // napkin.QUERY_KINDS: the table every front end lists its kinds from (db/query_kinds.h).
  module.def("_query_kinds", [] {
    std::vector<py::tuple> rows;
    for (const db::QueryKindSpec& kind : db::QueryKinds())
      rows.push_back(py::make_tuple(kind.name, kind.description, kind.takes_limits));
    return rows;
  });
  // The output formats of `napkin export` (app/export.h), in table order: (name, description,
  // needs_result, needs_rotation, folder).
  module.def("_export_formats", [] {
    py::list formats;
    for (const app::ExportFormat& format : app::ExportFormats())
      formats.append(py::make_tuple(std::string(format.name), std::string(format.description),
                                    format.input != app::ExportInput::kRecordedChannels,
                                    format.needs_rotation, format.folder));
    return formats;
  });
  py::class_<ReadOnlyCatalogue>(module, "Catalogue")
      .def(py::init([](const std::string& path) {
             return Translated(path, [&] { return std::make_unique<ReadOnlyCatalogue>(path); });
           }),
           py::arg("path"))
      .def_property_readonly("path", &ReadOnlyCatalogue::path)
      .def_property_readonly("closed", &ReadOnlyCatalogue::closed)
      .def("close", &ReadOnlyCatalogue::Close)
      .def(
          "query",
          [](ReadOnlyCatalogue& self, const std::string& kind,
             const std::optional<std::vector<std::string>>& where,
             const std::optional<std::vector<std::string>>& sort, const std::optional<std::string>& limit,
             const std::optional<std::string>& config, const std::optional<std::vector<std::string>>& series,
             const std::optional<std::vector<std::string>>& variant,
             const std::optional<std::string>& limits) {
            return Translated(self.path(), [&] {
              app::Query query;
              query.kind = kind;
              query.filters.where = AsList(where);
              query.filters.sort = AsList(sort);
              query.filters.limit = limit.value_or("");
              query.filters.config = config.value_or("");
              query.filters.tests.series = AsList(series);
              query.filters.tests.variants = AsList(variant);
              query.filters.front_end = app::FrontEnd::kPython;
              query.limits = limits;
              return self.Query(query);
            });
          },
          py::arg("kind"), py::arg("where"), py::arg("sort"), py::arg("limit"), py::arg("config"),
          py::arg("series"), py::arg("variant"), py::arg("limits") = py::none())
      .def(
          "compare",
          [](ReadOnlyCatalogue& self, const std::vector<std::pair<std::string, std::string>>& options,
             bool typed) {
            return Translated(self.path(), [&] {
              // Python's arguments as `napkin compare`'s options, one parser for both
              // (app/request_options.h).
              app::RequestOptions request_options(app::FrontEnd::kPython);
              for (const auto& [name, value] : options) request_options.Add(name, value);
              return self.Compare(app::ParseCompareRequest(request_options), typed);
            });
          },
          py::arg("options"), py::arg("typed"))
      .def(
          "export",
          [](ReadOnlyCatalogue& self, const std::string& test_id,
             const std::vector<std::pair<std::string, std::string>>& options, const std::string& out,
             bool force) {
            Translated(self.path(), [&] {
              // Python's arguments as `napkin export`'s options, one parser for both (app/request_options.h).
              app::RequestOptions request_options(app::FrontEnd::kPython);
              for (const auto& [name, value] : options) request_options.Add(name, value);
              self.Export(app::ParseExportRequest(test_id, request_options), out, force);
              return 0;
            });
          },
          py::arg("test_id"), py::arg("options"), py::arg("out"), py::arg("force"))
      .def(
          "channels",
          [](ReadOnlyCatalogue& self, const std::string& test_id, bool derived,
             const std::optional<std::string>& config) {
            return Translated(self.path(), [&] { return self.Channels(test_id, derived, config); });
          },
          py::arg("test_id"), py::arg("derived"), py::arg("config"))
      .def(
          "test_inputs",
          [](ReadOnlyCatalogue& self, const std::string& test_id) {
            return Translated(self.path(), [&] { return self.TestInputs(test_id); });
          },
          py::arg("test_id"));
}

}  // namespace napkin::python
