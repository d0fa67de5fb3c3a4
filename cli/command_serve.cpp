// `napkin serve`: the lab's long-running service (serve/service.h,
// docs/serve.md): the catalogue answered over a read-only HTTP API until
// SIGTERM. This file only reads the options.
#include "cli/command.h"
#include "cli/diagnostics.h"
#include "cli/option_checks.h"
#include "serve/service.h"

namespace napkin::cli {
namespace {

class ServeCommand : public Command {
 public:
  CLI::App* Setup(CLI::App& app, const GlobalOptions& global) override {
    global_ = &global;
    CLI::App* sub =
        app.add_subcommand("serve", "answer the catalogue over HTTP until SIGTERM (docs/serve.md)");
    sub->add_option("--listen", options_.listen,
                    "HOST:PORT to listen on (port 0: any free one; an address other than loopback needs "
                    "--token-file)")
        ->capture_default_str();
    sub->add_option("--token-file", options_.token_file,
                    "file holding the bearer token every request must carry (Authorization: Bearer TOKEN)")
        ->check(PathCheck("--token-file"));
    sub->add_option("--threads", options_.threads, "request threads")
        ->check(WholeNumberCheck("--threads", 1, 256))
        ->capture_default_str();
    sub->add_option("--busy-timeout", busy_timeout_s_,
                    "seconds a request waits for a catalogue another process holds locked, then answers 503")
        ->check(WholeNumberCheck("--busy-timeout", 0, 3600))
        ->capture_default_str();
    sub->add_option("--inbox", options_.inbox,
                    "folder whose tests (<inbox>/<series>/<variant>/...) are imported and processed as they "
                    "arrive; only read");
    sub->add_option(
           "--settle", options_.settle_s,
           "seconds a test's files must stay unchanged before it is imported (or a <name>.ready marker)")
        ->capture_default_str();
    sub->add_option("--poll", options_.poll_s,
                    "look at the inbox every this many seconds instead of inotify (network file systems)");
    return sub;
  }

  int Run() override {
    options_.db_path = global_->db_path;
    options_.busy_timeout_ms = busy_timeout_s_ * 1000;
    // A service's log is read later (the journal, a file): its warnings and errors need their time.
    options_.on_listening = [] { TimestampEveryLogLine(); };
    serve::RunService(options_);
    return kExitOk;
  }

 private:
  const GlobalOptions* global_ = nullptr;
  serve::ServeOptions options_;
  int busy_timeout_s_ = 10;
};

}  // namespace

std::unique_ptr<Command> MakeServeCommand() { return std::make_unique<ServeCommand>(); }

}  // namespace napkin::cli
