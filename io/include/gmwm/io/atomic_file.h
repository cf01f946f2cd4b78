#pragma once
// Writes an output file all-or-nothing: the content goes to a temporary file beside the
// target, which is renamed over the target only on success (DESIGN.md error policy: no
// partial output files).

#include <string>
#include <string_view>

namespace gmwm::io {

/// Writes `content` to `path` atomically. Throws InputError (naming the path) when the
/// folder is missing or not writable. `path` "-" writes to standard output.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace gmwm::io
