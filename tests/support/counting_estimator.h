#pragma once
// A WV estimator that counts the series it reads and hands them to another: what tests of
// the replicate studies use to see which replicate's draws went through which estimator.
#include <atomic>
#include <cstdint>
#include <string>

#include "gmwm/engine/wavelet_variance.h"

namespace gmwm::test {

class CountingEstimator final : public WvEstimator {
 public:
  explicit CountingEstimator(const WvEstimator& inner) : inner_(inner) {}
  WaveletVariance compute(const double* x, std::int64_t n, int levels, double alpha) const override {
    ++calls_;
    return inner_.compute(x, n, levels, alpha);
  }
  std::string name() const override { return inner_.name(); }
  int calls() const { return calls_.load(); }

 private:
  const WvEstimator& inner_;
  mutable std::atomic<int> calls_{0};
};

}  // namespace gmwm::test
