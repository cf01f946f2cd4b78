#pragma once
// The library's messages name the command line's options (--freq, --units, ...): the CLI
// prints them as they are. The other faces fill the same requests from their own inputs and
// say the same refusal in their own words: the web app names its request's JSON fields
// ("units", "unit_check": false), Python its keyword arguments (units, unit_check=False).
// One table of options and the fields that set them, here, for every face (issue 45: the web
// app had its own table and Python none, so gmwm.fit(..., units="furlong") said "--units").

#include <string>

namespace gmwm::io {

/// Who reads a message.
enum class Face { kCli, kWeb, kPython };

/// `message` (the library's, naming CLI options) in the words of `face`: each option of the
/// table replaced by the field that sets it on that face, whole options only ("--model" is
/// not read inside "--models"). kCli returns it unchanged.
std::string option_wording(std::string message, Face face);

}  // namespace gmwm::io
