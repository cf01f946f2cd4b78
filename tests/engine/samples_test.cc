// gmwm::Samples: a series in memory or in an unlinked temporary file, and the Haar
// transform of a series in a file (prefix sums in a temporary file, pages released behind
// each pass) giving the same sums to the last bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <filesystem>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/haar_modwt.h"
#include "gmwm/engine/samples.h"

namespace {

std::vector<double> series(std::size_t n) {
  std::vector<double> x(n);
  double rw = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    rw += 1e-3 * std::sin(0.7 * static_cast<double>(i) + 0.3);
    x[i] = std::cos(1.3 * static_cast<double>(i)) + rw;
  }
  return x;
}

gmwm::Samples in_file(const std::vector<double>& x, std::size_t chunk) {
  gmwm::SampleFileWriter w;
  for (std::size_t b = 0; b < x.size(); b += chunk) w.append(x.data() + b, std::min(chunk, x.size() - b));
  return w.finish();
}

}  // namespace

TEST(Samples, AVectorIsHeldInMemoryAndCopiesShareIt) {
  const gmwm::Samples s(std::vector<double>{1.0, 2.0, 3.0});
  const gmwm::Samples copy = s;
  EXPECT_FALSE(s.in_file());
  EXPECT_EQ(copy.data(), s.data());
  EXPECT_EQ(s.size(), 3u);
  EXPECT_EQ(s.back(), 3.0);
  ASSERT_NE(s.vector(), nullptr);
  EXPECT_EQ(s.to_vector(), (std::vector<double>{1.0, 2.0, 3.0}));
}

TEST(Samples, AWriterHandsOverTheSeriesInAFileValueForValue) {
  // 300,001 values appended in odd-sized pieces: across the writer's 1 MiB buffer.
  const std::vector<double> x = series(300001);
  const gmwm::Samples s = in_file(x, 77777);
  EXPECT_TRUE(s.in_file());
  EXPECT_EQ(s.vector(), nullptr);
  EXPECT_EQ(s.size(), x.size());
  EXPECT_TRUE(s == gmwm::Samples(x));
  EXPECT_TRUE(gmwm::detail::in_sample_file(s.data(), s.size()));
  EXPECT_FALSE(gmwm::detail::in_sample_file(x.data(), x.size()));
}

TEST(Samples, ReleasingPagesOfAFileKeepsItsValuesAndLeavesOtherMemoryAlone) {
  const std::vector<double> x = series(1 << 20);
  const gmwm::Samples s = in_file(x, 1 << 16);
  gmwm::detail::release_file_pages(s.data(), s.data() + s.size());
  EXPECT_TRUE(s == gmwm::Samples(x));  // read back from the file
  std::vector<double> y = x;
  gmwm::detail::release_file_pages(y.data(), y.data() + y.size());  // not a file: untouched
  EXPECT_EQ(y, x);
}

TEST(Samples, TheTransformOfASeriesInAFileGivesTheSameWvToTheLastBit) {
  // 2^21 + 3 samples: more than one block of the passes (2^20), and a length that leaves
  // a tail to the four-accumulator loop.
  const std::vector<double> x = series((std::size_t{1} << 21) + 3);
  const gmwm::Samples s = in_file(x, 1 << 18);
  const auto n = static_cast<std::int64_t>(x.size());
  const gmwm::HaarModwt mem(x.data(), n), file(s.data(), n);
  for (int j = 1; j <= mem.max_levels(); ++j) EXPECT_EQ(mem.sum_of_squares(j), file.sum_of_squares(j)) << "level " << j;
  EXPECT_EQ(mem.noise_floor(3), file.noise_floor(3));
  std::vector<double> a, b;
  mem.coefficients(5, a);
  file.coefficients(5, b);
  EXPECT_EQ(a, b);
  double mean_square = 0.0;
  for (double v : a) mean_square += v * v / static_cast<double>(a.size());
  EXPECT_EQ(mem.count_above(5, 1.5 * mean_square), file.count_above(5, 1.5 * mean_square));
  EXPECT_GT(file.count_above(5, 1.5 * mean_square), 0);
  EXPECT_EQ(gmwm::classical_wv(x.data(), n).wv, gmwm::classical_wv(s.data(), n).wv);
}

TEST(Samples, LeaveNoFileInTheTemporaryFolderWhileTheyLiveOrAfter) {
  // A private TMPDIR, so that other processes' files do not count.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gmwm_samples_test_tmpdir";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const char* old = std::getenv("TMPDIR");
  const std::string saved = old ? old : "";
  ::setenv("TMPDIR", dir.c_str(), 1);
  EXPECT_EQ(gmwm::detail::temporary_folder(), dir.string());
  {
    const gmwm::Samples s = in_file(series(100000), 4096);
    const gmwm::HaarModwt t(s.data(), static_cast<std::int64_t>(s.size()));
    EXPECT_GT(t.sum_of_squares(1), 0.0);
    EXPECT_TRUE(std::filesystem::is_empty(dir));  // unlinked at creation
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  if (old)
    ::setenv("TMPDIR", saved.c_str(), 1);
  else
    ::unsetenv("TMPDIR");
  std::filesystem::remove_all(dir);
}
