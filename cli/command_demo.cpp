// `napkin demo`: a catalogue of the padding series and the report's
// validation scenario, processed, compared and reported (cli/demo_session.h).
#include <string>

#include "cli/command.h"
#include "cli/demo_session.h"
#include "cli/option_checks.h"

namespace napkin::cli {
namespace {

class DemoCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions&) override {
    CLI::App* sub = app.add_subcommand("demo",
                                       "build a demo catalogue (padding series + the report's validation "
                                       "scenarios), run it, show the results");
    sub->add_option("--out,--dir", request_.dir,
                    "folder of the demo, new or empty or an earlier demo's: its catalogue napkin.db (rebuilt "
                    "on every run), report and files")
        ->capture_default_str()
        ->check(PathCheck("--out"));
    sub->add_option("--threads", request_.threads, "worker threads (default: all cores)")
        ->check(WholeNumberCheck("--threads", 1));
    sub->add_option("--limits", request_.limits,
                    "limits the padding verdict checks: a limits preset (config/limits) or a JSON file "
                    "(repeatable; default: fmvss201u and euro-ncap-aop-v9.3-frontal-head-hiii50m)")
        ->check(PathCheck("--limits"))
        ->allow_extra_args(false);
    return sub;
  }

  int Run() override {
    RunDemo(request_);
    return kExitOk;
  }

 private:
  DemoRequest request_;
};

}  // namespace

std::unique_ptr<Command> MakeDemoCommand() { return std::make_unique<DemoCommand>(); }

}  // namespace napkin::cli
