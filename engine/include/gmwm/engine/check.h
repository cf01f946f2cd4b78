#pragma once
// Argument checks for the math kernels (modelled on Stan Math's check_* family).
// Each check throws gmwm::InvalidArgument with a uniform message:
//   "<function>: <name> is <value>, but must be <requirement>"
// These guard programming errors and invalid numeric arguments; user-facing input
// validation (files, model strings, options) raises gmwm::InputError instead.

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace gmwm {

class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

namespace detail {
[[noreturn]] void throw_check(std::string_view function, std::string_view name, double value,
                              std::string_view requirement);
}  // namespace detail

inline void check_finite(std::string_view function, std::string_view name, double x) {
  if (!std::isfinite(x)) detail::throw_check(function, name, x, "finite");
}
inline void check_positive(std::string_view function, std::string_view name, double x) {
  if (!(x > 0.0) || !std::isfinite(x)) detail::throw_check(function, name, x, "positive and finite");
}
inline void check_nonnegative(std::string_view function, std::string_view name, double x) {
  if (!(x >= 0.0) || !std::isfinite(x)) detail::throw_check(function, name, x, "non-negative and finite");
}
/// Open interval (lo, hi).
inline void check_open_interval(std::string_view function, std::string_view name, double x, double lo, double hi) {
  if (!(x > lo && x < hi))
    detail::throw_check(function, name, x, "in (" + std::to_string(lo) + ", " + std::to_string(hi) + ")");
}
inline void check_probability(std::string_view function, std::string_view name, double x) {
  if (!(x > 0.0 && x < 1.0)) detail::throw_check(function, name, x, "in (0, 1)");
}
inline void check_at_least(std::string_view function, std::string_view name, double x, double lo) {
  if (!(x >= lo)) detail::throw_check(function, name, x, "at least " + std::to_string(lo));
}
void check_size_match(std::string_view function, std::string_view name_a, std::size_t a, std::string_view name_b,
                      std::size_t b);

}  // namespace gmwm
