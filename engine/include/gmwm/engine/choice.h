#pragma once
// An option that takes one of an enum's names (--omega model, --penalty bic, ...). Each enum
// lists its names once, beside its parser (fit.h's omega_kind_names, select.h's ...), and
// every face builds its check and its refusal from that list: the CLI's validator, Python's
// error and the web app's. The refusal is one: "found 'nope', expected model, diag, full or
// bootstrap", after the option as each face names it (io::option_wording).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace gmwm {

/// The names as a sentence reads them: "a", "a or b", "a, b or c".
std::string in_words(const std::vector<std::string>& names);

/// The one refusal of a text that is none of the names: "found '<text>', expected <in_words>".
std::string unknown_choice(const std::string& text, const std::vector<std::string>& names);

/// The value among `all` whose to_string is `text`, or nullopt.
template <class E, std::size_t N>
std::optional<E> parse_among(const std::string& text, const E (&all)[N]) {
  for (E e : all)
    if (text == to_string(e)) return e;
  return std::nullopt;
}

/// The to_string names of `all`, in its order.
template <class E, std::size_t N>
std::vector<std::string> names_among(const E (&all)[N]) {
  std::vector<std::string> out;
  for (E e : all) out.emplace_back(to_string(e));
  return out;
}

}  // namespace gmwm
