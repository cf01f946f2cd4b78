#include "gmwm/io/option_wording.h"

#include <cctype>
#include <string_view>

namespace gmwm::io {
namespace {

// An option of the command line and the request field that sets it (the same name on the
// web app's requests and Python's keyword arguments); for a switch, the value the option
// stands for. `unit`: the option's argument when the message shows it ("--freq HZ").
struct OptionField {
  std::string_view option;
  std::string_view field;
  std::string_view value = {};
  std::string_view unit = {};
};

// Longer spellings first where one option's text starts another's ("--freq HZ", "--freq").
constexpr OptionField kOptionFields[] = {
    {"--freq HZ", "freq", {}, "Hz"},
    {"--freq", "freq"},
    {"--columns", "columns"},
    {"--topic", "topic"},
    {"--units", "units"},
    {"--no-unit-check", "unit_check", "false"},
    {"--partial", "partial", "true"},
    {"--consistent-for", "consistent_for"},
    {"--temperature", "temperature"},
    {"--inflate", "inflate"},
    {"--replicates", "replicates"},
    {"--model", "model"},
    {"--models", "models"},
    {"--omega", "omega"},
    {"--optimism", "optimism"},
    {"--penalty", "penalty"},
    {"--estimator", "estimator"},
    {"--eff", "eff"},
    {"--robust", "robust", "true"},
    {"--no-spike-screen", "spike_screen", "false"},
    {"--alpha", "alpha"},
    {"--levels", "levels"},
    {"--sensor", "sensor"},
    {"--trajectory", "trajectory"},
    {"--adev-points", "adev_points"},
    {"--kf-rate", "kf_rate"},
    {"--max-evaluations", "max_evaluations"},
    {"--decimate-filter", "decimate_filter"},
    {"--decimate", "decimate"},
    {"--data", "data"},
    {"--gaps join", "gaps", "join"},
    {"--gaps", "gaps"},
    {"--memory MB", "memory", {}, "MB"},
    {"--memory", "memory"},
    {"--value", "value"},
    {"--exclude-taus", "exclude_taus"},
    {"--record", "record"},
    {"--curve-confidence", "confidence"},
    {"--kind", "kind"},
    {"--taus", "taus"},
    {"--confidence", "confidence"},
    {"--intervals", "intervals"},
    {"--noise-alpha", "noise_alpha"},
    {"--hat", "hat", "true"},
};

bool option_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_'; }

std::string field_words(const OptionField& f, Face face) {
  std::string out;
  if (face == Face::kWeb) {
    out = "\"" + std::string(f.field) + "\"";
    const bool literal = f.value == "true" || f.value == "false";
    if (!f.value.empty()) out += ": " + (literal ? std::string(f.value) : "\"" + std::string(f.value) + "\"");
  } else {
    out = std::string(f.field);
    // Python's literals: True / False; a text value quoted.
    if (f.value == "true")
      out += "=True";
    else if (f.value == "false")
      out += "=False";
    else if (!f.value.empty())
      out += "=\"" + std::string(f.value) + "\"";
  }
  if (!f.unit.empty()) out += " (" + std::string(f.unit) + ")";
  return out;
}

}  // namespace

std::string option_wording(std::string message, Face face) {
  if (face == Face::kCli) return message;
  for (const OptionField& f : kOptionFields) {
    const std::string to = field_words(f, face);
    for (std::size_t p = message.find(f.option); p != std::string::npos;) {
      const std::size_t end = p + f.option.size();
      // Whole options: not the tail of a longer option, nor its head.
      const bool whole =
          (p == 0 || !option_char(message[p - 1])) && (end == message.size() || !option_char(message[end]));
      if (!whole) {
        p = message.find(f.option, end);
        continue;
      }
      message.replace(p, f.option.size(), to);
      p = message.find(f.option, p + to.size());
    }
  }
  return message;
}

}  // namespace gmwm::io
