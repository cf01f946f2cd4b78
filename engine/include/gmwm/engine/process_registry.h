#pragma once
// Registry of process types by name, built explicitly at its first use (no reliance on
// load-time side effects, so static builds keep every process). Each built-in process
// file defines its registration function with
//
//   GMWM_REGISTER_PROCESS(Ar1Process, "AR1", "first-order autoregression: AR1(phi, sigma2)");
//   GMWM_REGISTER_PROCESS(ArmaProcess, "ARMA", "...", "p", "q");   // structural arguments
//
// and names its type in engine/src/processes/builtin_processes.h, the list the registry
// calls. An application adds its own type with ProcessRegistry::instance().add(entry).
//
// Structural arguments (integers written in the model string, e.g. ARMA(p=2,q=1)) are
// consumed by the factory; every other key=value in a model string is a parameter value.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gmwm/engine/process.h"

namespace gmwm {

struct ProcessArgs {
  ProcessContext context;
  std::map<std::string, long> structural;  ///< e.g. {"p": 2, "q": 1}
};

using ProcessFactory = std::function<std::unique_ptr<Process>(const ProcessArgs&)>;

struct ProcessEntry {
  std::string name;
  std::vector<std::string> structural_keys;
  ProcessFactory factory;
  std::string summary;  ///< one line for `gmwm --help`-like listings
};

class ProcessRegistry {
 public:
  static ProcessRegistry& instance();
  bool add(ProcessEntry entry);
  /// nullptr when unknown. Names are matched case-insensitively.
  const ProcessEntry* find(const std::string& name) const;
  std::vector<std::string> names() const;
  /// Creates a process; throws InputError for an unknown name or invalid structure.
  std::unique_ptr<Process> create(const std::string& name, const ProcessArgs& args) const;

 private:
  std::map<std::string, ProcessEntry> entries_;  // key: upper-case name
};

}  // namespace gmwm

/// For the library's built-in processes only: defines `void register_process_<Type>(
/// ProcessRegistry&)` for a process type (an unqualified name) whose constructor takes
/// (const ProcessArgs&), at namespace gmwm scope in the type's file; the registry calls it
/// because builtin_processes.h lists the type. It registers nothing by itself: an
/// application adds its own type with ProcessRegistry::instance().add(entry).
#define GMWM_REGISTER_PROCESS(Type, Name, Summary, ...)                                                      \
  void register_process_##Type(::gmwm::ProcessRegistry& registry) {                                          \
    registry.add(::gmwm::ProcessEntry{Name, std::vector<std::string>{__VA_ARGS__},                           \
                                      [](const ::gmwm::ProcessArgs& a) -> std::unique_ptr<::gmwm::Process> { \
                                        auto p = std::make_unique<Type>(a);                                  \
                                        p->set_context(a.context);                                           \
                                        return p;                                                            \
                                      },                                                                     \
                                      Summary});                                                             \
  }                                                                                                          \
  static_assert(true, "the caller's ';' ends this")
