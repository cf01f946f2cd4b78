#pragma once
// Writes one output file all-or-nothing: OutputSet (output_set.h) with a single file. The
// content goes to a temporary file beside the target, renamed over it only on success; a
// target that is a folder, a device, a FIFO or a symbolic link is refused (docs/design.md section 3, error
// policy: no partial output files, nothing of the user's clobbered).

#include <string>
#include <string_view>

namespace gmwm::io {

/// Writes `content` to `path` atomically. Throws InputError (naming the path) when the
/// folder is missing or not writable, or the target is not a regular file. `path` "-"
/// writes to standard output (errors checked).
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace gmwm::io
