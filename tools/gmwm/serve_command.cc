// gmwm serve [FOLDER] [--port N] [--host ADDRESS] [--max-upload MB] [--threads N] [--seed S]
// The web app (docs/serve.md): builds a model by hand in a browser, over the same library
// calls as the other commands. Parses, starts serve::Server, prints its address, serves
// until Ctrl-C or SIGTERM.
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <thread>

#include <pthread.h>

#include "common.h"
#include "gmwm/engine/error.h"
#include "gmwm/serve/server.h"

namespace gmwm::cli {
namespace {

struct ServeArgs {
  std::string folder = ".";
  std::string host = "127.0.0.1";
  int port = 8080;
  double max_upload_mb = static_cast<double>(serve::kDefaultMaxUploadBytes) / 1e6;
  std::optional<double> max_upload_total_mb;
  std::optional<double> memory_mb;
  std::vector<std::string> allowed_hosts;
};

// The environment variable a script sets to choose the access token (a command-line option
// would show it to every user of the machine in the process list).
constexpr const char* kTokenVariable = "GMWM_SERVE_TOKEN";

// The addresses that reach only this machine.
bool is_loopback(const std::string& host) {
  return host == "127.0.0.1" || host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// A ServeOptions message as the user set the field: the option or variable that sets it.
std::string as_option(const std::string& why) {
  constexpr std::pair<const char*, const char*> kFieldOptions[] = {{"token:", kTokenVariable},
                                                                   {"allowed_hosts:", "--allow-host"},
                                                                   {"max_upload_bytes:", "--max-upload"},
                                                                   {"max_upload_total_bytes:", "--max-upload-total"},
                                                                   {"port:", "--port"},
                                                                   {"host:", "--host"},
                                                                   {"folder:", "FOLDER"}};
  for (const auto& [field, option] : kFieldOptions)
    if (why.rfind(field, 0) == 0) return option + why.substr(std::string(field).size() - 1);
  return why;
}

// Parse: the server's options from the arguments (InputError naming the option).
serve::ServeOptions serve_options(const ServeArgs& args, const CommonOptions& common) {
  serve::ServeOptions o;
  o.folder = args.folder;
  o.host = args.host;
  o.port = args.port;
  o.max_upload_bytes = static_cast<std::int64_t>(args.max_upload_mb * 1e6);
  // The total holds at least one upload of the largest size.
  o.max_upload_total_bytes = args.max_upload_total_mb
                                 ? static_cast<std::int64_t>(*args.max_upload_total_mb * 1e6)
                                 : std::max(serve::kDefaultMaxUploadTotalBytes, o.max_upload_bytes);
  o.seed = common.seed;
  if (args.memory_mb) o.memory_budget = *args.memory_mb * 1e6;
  o.allowed_hosts = args.allowed_hosts;
  if (const char* t = std::getenv(kTokenVariable); t && *t) o.token = t;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError("serve: " + as_option(why));
  return o;
}

int run_serve(const ServeArgs& args, const CommonOptions& common) {
  auto threads = apply_common_options(common);
  const serve::ServeOptions o = serve_options(args, common);
  if (!is_loopback(o.host))
    warn("serving on " + o.host + ": anyone who can reach this address and has the token in the address below can " +
         "read the recordings under " + o.folder + " and run analyses; the connection is not encrypted");

  // SIGINT and SIGTERM are taken by one thread that stops the server: blocked here, before
  // the server's threads start, so that they inherit the mask and never take them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  serve::Server server(o);
  server.bind();
  std::cout << "gmwm serve: " << server.url() << " (folder " << printable_line(o.folder) << "); Ctrl-C stops it"
            << std::endl;
  if (const std::string& why = server.app().plots_unavailable(); !why.empty())
    warn("the page will show no plots (its tables, numbers and exports work): " + why);
  std::thread waiter([&] {
    int signal = 0;
    sigwait(&stop_signals, &signal);
    server.stop();
  });
  server.run();
  // run() also ends when the listening socket fails: wake the waiter then.
  pthread_kill(waiter.native_handle(), SIGTERM);
  waiter.join();
  return 0;
}

}  // namespace

Command add_serve_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* sub = app.add_subcommand(
      "serve",
      "A local web app to build a model by hand: pick a recording of FOLDER (or upload one), look at its WV and "
      "Allan deviation, tick components, fit, select, overlay a datasheet or simulator model, export");
  sub->add_option("FOLDER", args->folder, "The recordings to offer (nothing outside it is read)")
      ->capture_default_str();
  sub->add_option("--port", args->port, "TCP port (0: a free one, printed)")
      ->type_name("N")
      ->transform(whole_number(0, 65535))
      ->capture_default_str();
  sub->add_option("--host", args->host,
                  "Address to listen on; anything but loopback lets other machines in (with the token)")
      ->type_name("ADDRESS")
      ->capture_default_str();
  sub->add_option("--allow-host", args->allowed_hosts,
                  "Another name this server may be reached by (its Host), besides localhost, 127.0.0.1, [::1] and "
                  "--host; repeatable")
      ->type_name("NAME");
  sub->add_option("--max-upload", args->max_upload_mb, "Largest upload in MB (413 beyond)")
      ->type_name("MB")
      ->transform(decimal_number([](double x) { return x >= 1e-6 && x <= 1e9; }, "a size in MB from 1e-06 to 1e+09"))
      ->capture_default_str();
  sub->add_option("--max-upload-total", args->max_upload_total_mb,
                  "MB all uploads may hold on disk at once (the oldest are removed to make room; default 2048, or "
                  "--max-upload if larger)")
      ->type_name("MB")
      ->transform(decimal_number([](double x) { return x >= 1e-6 && x <= 1e9; }, "a size in MB from 1e-06 to 1e+09"));
  sub->add_option("--memory", args->memory_mb,
                  "MB a recording's values may take in memory before they go to temporary files")
      ->type_name("MB")
      ->transform(memory_megabytes());
  sub->add_option("--threads", common.threads, "Worker threads of the analyses (default: all cores)")
      ->type_name("N")
      ->transform(whole_number(1, 4096));
  sub->add_option("--seed", common.seed, "Random seed of every analysis (as the other commands' --seed)")
      ->type_name("S")
      ->transform(whole_number(0, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  sub->add_option("--log-level", common.log_level, "Library log level on stderr")
      ->type_name("LEVEL")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  return {sub, [args, &common] { return run_serve(*args, common); }};
}

}  // namespace gmwm::cli
