// `napkin transform`: one test, no catalogue — the seed program's job,
// non-interactive.
#include <spdlog/spdlog.h>

#include "app/transform.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "cli/triple_option.h"
#include "engine/solver.h"

namespace napkin::cli {
namespace {

class TransformCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions&) override {
    CLI::App* sub = app.add_subcommand("transform", "process one test file, no catalogue");
    sub->add_option("--array", options_.array, "array preset name or array JSON file")
        ->required()
        ->check(PathCheck("--array"));
    AddTripleOption(sub, "--orientation", options_.orientation_rad,
                    "initial orientation PHI,THETA,PSI (rad)");
    AddTripleOption(sub, "--initial-velocity", options_.initial_velocity_mps,
                    "initial CG velocity VX,VY,VZ in the fixed frame (m/s)");
    std::vector<std::string> solvers;
    std::string solver_help;
    for (const engine::SolverKind kind : engine::kSolverKinds) {
      solver_help += (solvers.empty() ? "" : " or ") + std::string(engine::NameOf(kind));
      solvers.emplace_back(engine::NameOf(kind));
    }
    sub->add_option("--solver", options_.solver, solver_help + " (default: the config's, exact)")
        ->check(OneOfCheck("--solver", solvers));
    sub->add_option("--config", options_.config, "processing config preset or JSON file")
        ->check(PathCheck("--config"));
    sub->add_option("--column", options_.csv_columns,
                    "CSV column NAME feeds slot SLOT, as SLOT=NAME (repeatable)")
        ->allow_extra_args(false);
    sub->add_option("input", options_.input, "input signals (CSV)")
        ->required()
        ->check(PathCheck("the input path"));
    sub->add_option("--out", options_.out, "derived-channel CSV to write")
        ->required()
        ->check(PathCheck("--out"));
    sub->add_option("--summary", options_.summary, "per-test summary JSON to write")
        ->check(PathCheck("--summary"));
    sub->add_option("--lsdyna", options_.lsdyna, "LS-DYNA keyword load curves to write")
        ->check(PathCheck("--lsdyna"));
    return sub;
  }

  int Run() override {
    const app::TransformReport report = app::RunTransform(options_);
    for (const auto& warning : report.warnings) spdlog::warn("{}", warning);
    return kExitOk;
  }

 private:
  app::TransformOptions options_;
};

}  // namespace

std::unique_ptr<Command> MakeTransformCommand() { return std::make_unique<TransformCommand>(); }

}  // namespace napkin::cli
