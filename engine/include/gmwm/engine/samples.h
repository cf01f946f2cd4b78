#pragma once
// gmwm::Samples: a read-only series of doubles, held in memory (a std::vector) or, for a
// record larger than the memory budget, in a temporary file mapped into memory. A series
// in a file costs no anonymous memory: its pages are the page cache's, read back when
// touched, and the Haar transform of such a series keeps its prefix sums in a temporary
// file too, releasing the pages it has passed (haar_modwt.h). Copies share the storage.
//
// Temporary files are created in $TMPDIR (default /tmp) and unlinked at once: nothing is
// left behind, whatever way the program ends.

#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace gmwm {

class Samples {
 public:
  Samples() = default;
  /// A series in memory (implicit: a vector is the common case).
  Samples(std::vector<double> values);  // NOLINT(google-explicit-constructor)
  Samples(std::initializer_list<double> values) : Samples(std::vector<double>(values)) {}

  const double* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const double* begin() const { return data_; }
  const double* end() const { return data_ + size_; }
  double operator[](std::size_t i) const { return data_[i]; }
  double front() const { return data_[0]; }
  double back() const { return data_[size_ - 1]; }
  operator std::span<const double>() const { return {data_, size_}; }  // NOLINT
  std::vector<double> to_vector() const { return {begin(), end()}; }
  /// True when the series is held in a temporary file.
  bool in_file() const { return file_ != nullptr; }
  /// The vector a series in memory is held in (for interfaces that take one); nullptr for
  /// a series in a file.
  const std::vector<double>* vector() const { return vector_.get(); }

  friend bool operator==(const Samples& a, const Samples& b);

 private:
  friend class SampleFileWriter;
  struct Mapping;
  std::shared_ptr<const std::vector<double>> vector_;
  std::shared_ptr<const Mapping> file_;
  const double* data_ = nullptr;
  std::size_t size_ = 0;
};

/// Writes a series to an unlinked temporary file as it comes, in a 1 MiB buffer, and
/// hands it over as Samples held in that file. Throws InputError when the temporary
/// folder cannot take it (naming the folder and the reason).
class SampleFileWriter {
 public:
  SampleFileWriter();
  ~SampleFileWriter();
  SampleFileWriter(const SampleFileWriter&) = delete;
  SampleFileWriter& operator=(const SampleFileWriter&) = delete;

  void append(const double* values, std::size_t count);
  std::size_t size() const { return count_; }
  /// The series written; the writer is empty afterwards.
  Samples finish();

 private:
  void flush();
  int fd_ = -1;
  std::vector<double> buffer_;
  std::size_t count_ = 0;
};

namespace detail {

/// The folder of gmwm's temporary files: $TMPDIR, else /tmp.
std::string temporary_folder();

/// True when [p, p + count) lies in the file of a Samples (a read-only shared mapping,
/// whose pages may be released: they are read back from the file when touched again).
bool in_sample_file(const double* p, std::size_t count);

/// Drops the whole pages of [begin, end) from this process's resident memory. Only for
/// memory in a sample file or a TemporaryArray (shared file mappings, whose contents
/// stay in the file); anything else is left alone.
void release_file_pages(const double* begin, const double* end);

/// A writable array of doubles in an unlinked temporary file (the Haar prefix sums of a
/// series held in a file).
class TemporaryArray {
 public:
  explicit TemporaryArray(std::size_t count);
  ~TemporaryArray();
  TemporaryArray(const TemporaryArray&) = delete;
  TemporaryArray& operator=(const TemporaryArray&) = delete;
  double* data() const { return data_; }
  std::size_t size() const { return count_; }

 private:
  double* data_ = nullptr;
  std::size_t count_ = 0;
};

}  // namespace detail

/// Calls f(block, offset) on x in consecutive blocks of 2^20 values, in order; when x is
/// held in a file, the pages of each block are released once it is done, so a pass over a
/// series of any length costs no memory that grows with it.
template <class F>
void for_each_block(std::span<const double> x, F&& f) {
  constexpr std::size_t kBlock = std::size_t{1} << 20;
  const bool file = detail::in_sample_file(x.data(), x.size());
  for (std::size_t b = 0; b < x.size(); b += kBlock) {
    const std::span<const double> part = x.subspan(b, std::min(kBlock, x.size() - b));
    f(part, b);
    if (file) detail::release_file_pages(part.data(), part.data() + part.size());
  }
}

}  // namespace gmwm
