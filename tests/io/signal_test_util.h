#pragma once
// Helpers for the signal reader/writer tests: small files in a temp folder, and the one
// line of an InputError.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::test {

/// Writes `content` to `dir/name` byte for byte and returns the path.
inline std::string write_text(const std::filesystem::path& dir, const std::string& name, const std::string& content) {
  const auto p = dir / name;
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}

/// `rows` data rows "time,x,y" at 100 Hz (time in seconds), values that vary.
inline std::string csv_rows(int rows, char delim = ',', bool with_time = true) {
  std::string s;
  char buf[128];
  for (int i = 0; i < rows; ++i) {
    if (with_time)
      std::snprintf(buf, sizeof buf, "%.2f%c%.6f%c%d\n", i * 0.01, delim, std::sin(i), delim, i % 7);
    else
      std::snprintf(buf, sizeof buf, "%.6f%c%d\n", std::sin(i), delim, i % 7);
    s += buf;
  }
  return s;
}

/// The message of the InputError read_signals() throws, or "no error".
inline std::string read_error(const std::string& path, const io::ReadOptions& options = {}) {
  try {
    io::read_signals(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace gmwm::test
