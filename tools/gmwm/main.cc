// gmwm: the command-line program (docs/cli.md). Exit codes: 0 success; 2 bad input or bad
// options (one line "gmwm: error: ..." on stderr, nothing written); 1 internal failure.

#include <cerrno>
#include <csignal>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "common.h"
#include "gmwm/engine/check.h"
#include "gmwm/engine/error.h"

namespace gmwm::cli {
// `gmwm export` (export_command.cc).
Command add_export_command(CLI::App& app, CommonOptions& common);
// `gmwm nav` (nav_command.cc), `gmwm plan` (plan_command.cc).
Command add_nav_command(CLI::App& app, CommonOptions& common);
Command add_plan_command(CLI::App& app, CommonOptions& common);
// `gmwm fleet` (fleet_command.cc).
Command add_fleet_command(CLI::App& app, CommonOptions& common);
Command add_serve_command(CLI::App& app, CommonOptions& common);
// `gmwm completion bash`, `gmwm man` (docs_command.cc): generated from the options above.
Command add_completion_command(CLI::App& app);
Command add_man_command(CLI::App& app);
}  // namespace gmwm::cli

namespace {

int fail(int code, const std::string& message) {
  // One printable line of bounded length: CLI11 sometimes adds newlines, a file's bytes may
  // be anything, and an option's value any length.
  std::cerr << "gmwm: error: " << gmwm::capped_line(gmwm::printable_line(message)) << std::endl;
  return code;
}

// Runs the chosen command. The table (or page) on standard output comes after the files:
// a closed pipe or a full disk there is still an error to report, not a silent exit 0.
int run_command(const gmwm::cli::Command& c) {
  const int code = c.run();
  std::cout.flush();
  if (!std::cout) {
    // errno still holds the failed write's reason unless something ran since.
    const int err = errno;
    const bool write_error = err == EPIPE || err == ENOSPC || err == EIO || err == EFBIG || err == EDQUOT;
    return fail(2, std::string("cannot write to standard output: ") +
                       (write_error ? std::strerror(err) : "write error") +
                       (err == EPIPE ? " (its reader closed it)" : ""));
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gmwm::cli;
  CLI::App app{
      "gmwm: wavelet variance and GMWM models of the stochastic errors of inertial "
      "sensors and other long, autocorrelated signals",
      "gmwm"};
  app.set_version_flag("--version", gmwm::report::version());
  app.require_subcommand(1);

  // Past a file-size limit (ulimit -f) write(2) must fail with EFBIG, so that the staged
  // outputs are removed and the error reported, rather than the process being killed by
  // SIGXFSZ with a temporary file left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  // A closed standard output (`gmwm ... --json - | head -c1`) must fail the write with EPIPE,
  // reported in one line with exit 2 and the staged outputs dropped, rather than kill the
  // process with SIGPIPE (exit 141, no message).
  std::signal(SIGPIPE, SIG_IGN);

  CommonOptions common;
  for (int i = 0; i < argc; ++i) common.argv.emplace_back(argv[i]);
  const Command commands[] = {add_wv_command(app, common),        add_fit_command(app, common),
                              add_select_command(app, common),    add_gap_command(app, common),
                              add_gap_check_command(app, common), add_simulate_command(app, common),
                              add_export_command(app, common),    add_nav_command(app, common),
                              add_plan_command(app, common),      add_stability_command(app, common),
                              add_fleet_command(app, common),     add_serve_command(app, common),
                              add_completion_command(app),        add_man_command(app)};
  // A first word that names no command: say so, listing them (CLI11 would only say that a
  // command is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const Command& c : commands) {
      names += (names.empty() ? "" : ", ") + c.app->get_name();
      known = known || c.app->get_name() == argv[1];
    }
    if (!known) return fail(2, std::string("unknown command '") + argv[1] + "', expected one of: " + names);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, e.what());
  }

  try {
    for (const Command& c : commands)
      if (c.app->parsed()) return run_command(c);
    return fail(2, "expected a command (gmwm --help lists them)");
  } catch (const gmwm::InputError& e) {
    return fail(2, e.what());
  } catch (const gmwm::InvalidArgument& e) {
    return fail(2, e.what());
  } catch (const std::exception& e) {
    return fail(1, std::string("internal failure: ") + e.what());
  } catch (...) {
    return fail(1, "internal failure: unknown exception");
  }
}
