#include "gmwm/engine/choice.h"

namespace gmwm {

std::string in_words(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return out;
}

std::string unknown_choice(const std::string& text, const std::vector<std::string>& names) {
  return "found '" + text + "', expected " + in_words(names);
}

}  // namespace gmwm
