#pragma once
// Errors caused by the user's input or configuration. The CLI maps them to exit code 2
// and prints what() as one line. The message names the input, the place (line/column
// where it applies) and what was expected.

#include <stdexcept>
#include <string>

namespace gmwm {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gmwm
