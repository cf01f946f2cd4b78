#include "gmwm/engine/check.h"

#include <sstream>

namespace gmwm {
namespace detail {

void throw_check(std::string_view function, std::string_view name, double value, std::string_view requirement) {
  std::ostringstream os;
  os.precision(17);
  os << function << ": " << name << " is " << value << ", but must be " << requirement;
  throw InvalidArgument(os.str());
}

}  // namespace detail

void check_size_match(std::string_view function, std::string_view name_a, std::size_t a, std::string_view name_b,
                      std::size_t b) {
  if (a == b) return;
  std::ostringstream os;
  os << function << ": size of " << name_a << " (" << a << ") and size of " << name_b << " (" << b << ") must match";
  throw InvalidArgument(os.str());
}

}  // namespace gmwm
