// The program's memory policy (tools/gmwm/allocation.cc, linked into this test program as
// into gmwm): its allocation functions keep the standard's contract, and a large block
// freed and allocated again is not faulted in again (issue 44: the replicate loops).
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstddef>
#include <limits>
#include <memory>
#include <new>
#include <vector>

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kPolicyBuilt = false;  // the sanitizer's allocator stays in place
#else
constexpr bool kPolicyBuilt = true;
#endif

long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// Touches every page of a block of `bytes`, as a series or its prefix sums are filled.
long faults_filling(std::size_t bytes) {
  const long before = minor_faults();
  std::vector<double> block(bytes / sizeof(double), 1.0);
  volatile double sink = block[block.size() / 2];
  static_cast<void>(sink);
  return minor_faults() - before;
}

TEST(GmwmAllocation, ZeroBytesGiveDistinctBlocksAndAnImpossibleSizeThrowsBadAlloc) {
  void* a = ::operator new(0);
  void* b = ::operator new(0);
  EXPECT_NE(a, nullptr);
  EXPECT_NE(a, b);
  ::operator delete(a);
  ::operator delete(b);
  EXPECT_THROW(static_cast<void>(::operator new(std::numeric_limits<std::size_t>::max() / 2)), std::bad_alloc);
}

TEST(GmwmAllocation, NothrowNewGivesNullInsteadOfThrowingAndArraysRoundTrip) {
  EXPECT_EQ(::operator new(std::numeric_limits<std::size_t>::max() / 2, std::nothrow), nullptr);
  EXPECT_EQ(::operator new[](std::numeric_limits<std::size_t>::max() / 2, std::nothrow), nullptr);
  auto big = std::make_unique<double[]>(std::size_t{1} << 21);  // 16 MiB: advised for huge pages
  big[0] = 1.0;
  big[(std::size_t{1} << 21) - 1] = 2.0;
  EXPECT_EQ(big[0] + big[(std::size_t{1} << 21) - 1], 3.0);
}

TEST(GmwmAllocation, ABlockFreedAndAllocatedAgainIsNotFaultedInAgain) {
  if (!kPolicyBuilt) GTEST_SKIP() << "built with a sanitizer: its allocator, not the program's policy";
  // 8 MiB, a 1e6-sample series: freed, glibc's default unmapped it (or trimmed the heap) and
  // the next replicate faulted its 2048 pages in again.
  constexpr std::size_t kBytes = std::size_t{8} << 20;
  static_cast<void>(faults_filling(kBytes));  // the first time: its pages come in
  const long again = faults_filling(kBytes);
  EXPECT_LT(again, 64) << "the freed block went back to the kernel: " << again << " page faults to fill it again";
}

}  // namespace
