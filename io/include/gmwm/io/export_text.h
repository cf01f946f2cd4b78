#pragma once
// The text of configuration files (io/export.h's renderers and the gap study's corrected
// configuration): numbers every reader reads back exactly, comments that a name from a file
// cannot break out of, and the exported figures of one sensor kind.

#include <string>
#include <string_view>
#include <vector>

#include "gmwm/io/export.h"

namespace gmwm::io::export_text {

/// A real number as every consumer reads it back exactly: the shortest text that round-trips
/// (std::to_chars), always with a '.' in the mantissa and a signed exponent, e.g. "0.00016968",
/// "2.0e-05", "200.0". PyYAML (Kalibr) reads a YAML 1.1 float only with a dot (and a signed
/// exponent), and ORB-SLAM3's Settings::readParameter<float> rejects a value OpenCV's
/// FileStorage parses as an integer ("IMU.Frequency: 200" aborts it; "200.0" does not).
std::string real(double x);

/// %.*g, for comments.
std::string num(double x, int digits = 6);

/// Lines as comments: "# <line>" each, "#" alone for empty lines; each line printable
/// (printable_line), so that a newline in a name cannot start a key of its own.
std::string yaml_comments(const std::vector<std::string>& lines);
/// Lines inside one XML comment <!-- ... -->; "--" (not allowed in XML comments) becomes "- -".
std::string xml_comment(const std::vector<std::string>& lines, const std::string& indent = "");
/// `text` as the content of one XML comment: one printable line (printable_line) without
/// "--", not ending with '-'; whatever a name holds, it cannot close the comment.
std::string xml_comment_text(std::string_view text);

/// The exported figures of `kind` (nullptr when the source has no column of that kind).
const KindExport* find_kind(const ExportResult& r, SensorKind kind);

}  // namespace gmwm::io::export_text
