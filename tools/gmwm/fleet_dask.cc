// The Dask runner of `gmwm fleet --scheduler` (fleet_dask.h): a child Python process
// (python -m gmwm._fleet_dask ADDRESS) reads every task line from its standard input, then
// writes each record line as the cluster finishes it.
#include "fleet_dask.h"

#include <cerrno>
#include <csignal>
#include <functional>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/fleet/fleet_record.h"

extern char** environ;

namespace gmwm::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// The folder holding this program.
fs::path program_folder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

// The folder holding the gmwm package for this program: the build tree's python/ beside the
// program, or an installation's lib/pythonX.Y/dist-packages (CMake's install, Debian's
// interpreter) or site-packages (pip's, in a virtual environment or elsewhere), relative to
// the prefix (GMWM_PYTHON_INSTALL_PARENT). Empty: leave the interpreter's own path alone.
std::string package_parent() {
  std::error_code ec;
  const fs::path here = program_folder();
  if (here.empty()) return {};
  if (fs::exists(here / "python" / "gmwm" / "__init__.py", ec)) return (here / "python").string();
#ifdef GMWM_PYTHON_INSTALL_PARENT
  for (const char* packages : {"dist-packages", "site-packages"}) {
    const fs::path installed = here.parent_path() / GMWM_PYTHON_INSTALL_PARENT / packages;
    if (fs::exists(installed / "gmwm" / "__init__.py", ec)) return installed.string();
  }
#endif
  return {};
}

// The interpreter of the bridge: GMWM_PYTHON, else the python3 beside this program (the
// virtual environment pip installed it into: that interpreter sees the environment's
// packages), else the one the module was built for, else python3 on the PATH.
std::string bridge_python() {
  if (const char* py = std::getenv("GMWM_PYTHON"); py && *py) return py;
  std::error_code ec;
  const fs::path here = program_folder();
  if (!here.empty() && fs::exists(here / "python3", ec)) return (here / "python3").string();
#ifdef GMWM_PYTHON_EXECUTABLE
  if (fs::exists(GMWM_PYTHON_EXECUTABLE, ec)) return GMWM_PYTHON_EXECUTABLE;
#endif
  return "python3";
}

// The environment of the child: this one, with the package's folder first on PYTHONPATH.
std::vector<std::string> child_environment() {
  std::vector<std::string> env;
  const std::string parent = package_parent();
  bool set = false;
  for (char** e = environ; *e; ++e) {
    std::string v = *e;
    if (!parent.empty() && v.rfind("PYTHONPATH=", 0) == 0) {
      v = "PYTHONPATH=" + parent + (v.size() > 11 ? ":" + v.substr(11) : "");
      set = true;
    }
    env.push_back(std::move(v));
  }
  if (!parent.empty() && !set) env.push_back("PYTHONPATH=" + parent);
  return env;
}

struct Child {
  pid_t pid = -1;
  int in = -1;   // its standard input (ours to write)
  int out = -1;  // its standard output (ours to read)
  int err = -1;  // its standard error: an unlinked temporary file (Dask's chatter, its reason)
};

// An unlinked temporary file for the child's standard error: read after it ends, so that a
// chatty child never blocks on a full pipe while this process reads its records.
int error_file() {
  const char* tmp = std::getenv("TMPDIR");
  std::string path = std::string(tmp && *tmp ? tmp : "/tmp") + "/gmwm-dask-XXXXXX";
  const int fd = ::mkostemp(path.data(), O_CLOEXEC);
  if (fd >= 0) ::unlink(path.c_str());
  return fd;
}

// The child's reason: the last line of its standard error that starts with the bridge's own
// prefix, else its last line.
std::string child_reason(int fd) {
  if (fd < 0) return {};
  std::string text;
  char buf[4096];
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t got; (got = ::read(fd, buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(got));
  std::string own, last;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    if (!line.empty()) last = line;
    if (line.rfind("gmwm fleet --scheduler", 0) == 0) own = line;
    start = end + 1;
  }
  return own.empty() ? last : own;
}

Child start_bridge(const std::string& address) {
  const std::string python = bridge_python();
  int to_child[2], from_child[2];
  if (::pipe2(to_child, O_CLOEXEC) != 0 || ::pipe2(from_child, O_CLOEXEC) != 0)
    throw InputError(std::string("--scheduler: cannot make a pipe: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, to_child[0], 0);
  posix_spawn_file_actions_adddup2(&actions, from_child[1], 1);
  const int err = error_file();
  if (err >= 0) posix_spawn_file_actions_adddup2(&actions, err, 2);
  std::vector<std::string> args = {python, "-m", "gmwm._fleet_dask", address};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env = child_environment();
  std::vector<char*> envp;
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  Child c;
  const int rc = ::posix_spawnp(&c.pid, python.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(to_child[0]);
  ::close(from_child[1]);
  if (rc != 0) {
    ::close(to_child[1]);
    ::close(from_child[0]);
    if (err >= 0) ::close(err);
    throw InputError("--scheduler: cannot start " + python +
                     " (set GMWM_PYTHON to the interpreter that has gmwm and "
                     "python3-distributed): " +
                     std::strerror(rc));
  }
  c.in = to_child[1];
  c.out = from_child[0];
  c.err = err;
  return c;
}

void write_all(int fd, const std::string& text) {
  std::size_t off = 0;
  while (off < text.size()) {
    const ssize_t w = ::write(fd, text.data() + off, text.size() - off);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0)
      throw InputError(std::string("--scheduler: the Dask bridge stopped reading its tasks: ") + std::strerror(errno));
    off += static_cast<std::size_t>(w);
  }
}

// The child's exit, as a phrase ("exit code 3", "signal 9").
std::string reap(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status))
    return WEXITSTATUS(status) == 0 ? std::string() : "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
  return "an unknown status";
}

// Hands each record line to `done`; the number of tasks handed back.
std::size_t read_records(int fd, std::size_t tasks, const std::function<void(std::size_t, const std::string&)>& done) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(::fdopen(fd, "r"), &std::fclose);
  if (!f) throw InputError(std::string("--scheduler: cannot read the Dask bridge: ") + std::strerror(errno));
  char* line = nullptr;
  std::size_t cap = 0;
  struct FreeLine {
    char*& p;
    ~FreeLine() { std::free(p); }
  } guard{line};
  std::size_t back = 0;
  while (::getline(&line, &cap, f.get()) >= 0) {
    Json j = Json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("k") || !j["k"].is_number_unsigned()) continue;
    const std::size_t k = j["k"].get<std::size_t>();
    if (k >= tasks) continue;
    if (j.contains("record") && j["record"].is_string())
      done(k, j["record"].get<std::string>());
    else
      done(k, fleet::failed_record_text(j.value("error", std::string("the worker gave no record"))));
    ++back;
  }
  return back;
}

}  // namespace

void check_scheduler_address(const std::string& address) {
  static const std::regex kAddress(R"(^((tcp|tls|inproc|ucx)://)?[A-Za-z0-9._\-\[\]:]+(:[0-9]{1,5})?$)");
  if (address.empty() || address.size() > 300 || !std::regex_match(address, kAddress))
    throw InputError("--scheduler: found '" + address +
                     "', expected a Dask scheduler's address such as tcp://10.0.0.5:8786 or 127.0.0.1:8786");
}

fleet::FleetRunner dask_runner(const std::string& address) {
  return [address](const std::vector<fleet::FleetTask>& tasks,
                   const std::function<void(std::size_t, const std::string&)>& done) {
    if (tasks.empty()) return;
    Child c = start_bridge(address);
    std::string lines;
    for (std::size_t k = 0; k < tasks.size(); ++k) lines += Json{{"k", k}, {"task", tasks[k].text}}.dump() + "\n";
    try {
      write_all(c.in, lines);
    } catch (...) {
      ::close(c.in);
      ::close(c.out);
      if (c.err >= 0) ::close(c.err);
      reap(c.pid);
      throw;
    }
    ::close(c.in);
    std::size_t back = 0;
    try {
      back = read_records(c.out, tasks.size(), done);
    } catch (...) {
      ::kill(c.pid, SIGTERM);
      if (c.err >= 0) ::close(c.err);
      reap(c.pid);
      throw;
    }
    const std::string how = reap(c.pid);
    const std::string reason = child_reason(c.err);
    if (c.err >= 0) ::close(c.err);
    if (back < tasks.size())
      throw InputError("--scheduler " + address + ": " + std::to_string(back) + " of " + std::to_string(tasks.size()) +
                       " recordings done when the Dask bridge ended (" + (how.empty() ? "exit code 0" : how) +
                       (reason.empty() ? std::string(")") : "): " + reason) +
                       (back > 0 ? "; those are cached: run again to resume" : ""));
  };
}

}  // namespace gmwm::cli
