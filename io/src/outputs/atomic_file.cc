#include "gmwm/io/atomic_file.h"

#include "gmwm/io/output_set.h"

namespace gmwm::io {

void write_file_atomically(const std::string& path, std::string_view content) {
  OutputSet out;
  out.declare("output", path);
  out.stage(path, content);
  out.commit();
}

}  // namespace gmwm::io
