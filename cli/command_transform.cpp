// `napkin transform`: one test of any input format `napkin import` reads, no
// catalogue — the seed program's job, non-interactive.
#include <spdlog/spdlog.h>

#include "app/transform.h"
#include "cli/command.h"
#include "cli/option_checks.h"
#include "cli/triple_option.h"
#include "engine/solver.h"
#include "ingest/input_formats.h"

namespace napkin::cli {
namespace {

class TransformCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions&) override {
    CLI::App* sub = app.add_subcommand("transform", "process one test file, no catalogue");
    sub->add_option("--array", options_.input.array,
                    "array preset name or array JSON file (default: the one the channel codes define)")
        ->check(PathCheck("--array"));
    sub->add_option("--channel-map", options_.input.channel_map,
                    "channel map preset or JSON file (inputs of channels with codes or SENATT/AXIS)")
        ->check(PathCheck("--channel-map"));
    sub->add_option("--position", position_,
                    "take the dummy at this position (test object and position, e.g. 11)");
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
    sub->add_option("--column", options_.input.csv_columns,
                    "CSV column NAME feeds slot SLOT, as SLOT=NAME (repeatable)")
        ->allow_extra_args(false);
    sub->add_option("input", options_.input.path, "one test: " + ingest::WhatToGive())
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
    if (position_) options_.input.position = *position_;
    const app::TransformReport report = app::RunTransform(options_);
    for (const auto& warning : report.warnings) spdlog::warn("{}", warning);
    return kExitOk;
  }

 private:
  app::TransformOptions options_;
  std::optional<std::string> position_;
};

}  // namespace

std::unique_ptr<Command> MakeTransformCommand() { return std::make_unique<TransformCommand>(); }

}  // namespace napkin::cli
