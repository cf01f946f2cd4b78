#include "gmwm/engine/process_registry.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "gmwm/engine/error.h"
#include "processes/builtin_processes.h"

namespace gmwm {

#define GMWM_DECLARE_REGISTRATION(Type) void register_process_##Type(ProcessRegistry& registry);
GMWM_BUILTIN_PROCESSES(GMWM_DECLARE_REGISTRATION)
#undef GMWM_DECLARE_REGISTRATION

namespace {
std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

ProcessRegistry& ProcessRegistry::instance() {
  // Built once, thread-safely, at the first use.
  static ProcessRegistry registry = [] {
    ProcessRegistry r;
#define GMWM_CALL_REGISTRATION(Type) register_process_##Type(r);
    GMWM_BUILTIN_PROCESSES(GMWM_CALL_REGISTRATION)
#undef GMWM_CALL_REGISTRATION
    return r;
  }();
  return registry;
}

bool ProcessRegistry::add(ProcessEntry entry) {
  const std::string key = upper(entry.name);
  return entries_.emplace(key, std::move(entry)).second;
}

const ProcessEntry* ProcessRegistry::find(const std::string& name) const {
  auto it = entries_.find(upper(name));
  return it == entries_.end() ? nullptr : &it->second;
}

std::vector<std::string> ProcessRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [k, e] : entries_) out.push_back(e.name);
  return out;
}

std::unique_ptr<Process> ProcessRegistry::create(const std::string& name, const ProcessArgs& args) const {
  const ProcessEntry* e = find(name);
  if (!e) {
    std::ostringstream os;
    os << "unknown process '" << name << "' (known: ";
    bool first = true;
    for (const auto& n : names()) {
      os << (first ? "" : ", ") << n;
      first = false;
    }
    os << ")";
    throw InputError(os.str());
  }
  return e->factory(args);
}

}  // namespace gmwm
