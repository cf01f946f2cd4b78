#pragma once
// Registry of process types by name. Each process file registers itself:
//
//   GMWM_REGISTER_PROCESS(Ar1Process, "AR1", {});          // no structural arguments
//   GMWM_REGISTER_PROCESS_WITH(ArmaProcess, "ARMA", {"p", "q"}, make_arma);
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

namespace detail {
struct ProcessRegistrar {
  explicit ProcessRegistrar(ProcessEntry e) { ProcessRegistry::instance().add(std::move(e)); }
};
}  // namespace detail

}  // namespace gmwm

#define GMWM_PP_CAT2(a, b) a##b
#define GMWM_PP_CAT(a, b) GMWM_PP_CAT2(a, b)

/// Registers a process type whose constructor takes (const ProcessArgs&).
#define GMWM_REGISTER_PROCESS(Type, Name, Summary, ...)                                    \
  static const ::gmwm::detail::ProcessRegistrar GMWM_PP_CAT(gmwm_registrar_, __LINE__){    \
      ::gmwm::ProcessEntry{Name, std::vector<std::string>{__VA_ARGS__},                    \
                           [](const ::gmwm::ProcessArgs& a) -> std::unique_ptr<::gmwm::Process> { \
                             auto p = std::make_unique<Type>(a);                           \
                             p->set_context(a.context);                                    \
                             return p;                                                     \
                           },                                                              \
                           Summary}}
