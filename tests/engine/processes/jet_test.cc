// Jet (engine/src/processes/jet.h): a Jet without its Hessian (order 1, what an optimiser's
// gradient uses) forms the gradient by the same operations as one with it (order 2), so the
// two gradients agree to the bit, and the order-2 derivatives are those of the formula.
#include <gtest/gtest.h>

#include <cmath>

#include "../../../engine/src/processes/jet.h"

namespace gmwm::internal {
namespace {

// Every operation of jet.h once: unary minus, the four operations between Jets and with
// doubles, each elementary function and a lifted one.
template <class T>
T every_operation(const T& x, const T& y) {
  using std::exp, std::expm1, std::log, std::log1p, std::sqrt;
  const T a = x * y - y / x + (2.0 - x) * 3.0 + 1.5 / y - (-x) / 4.0 + (x + 0.25);
  const T b = exp(x) * expm1(-y) + log(y) - log1p(x * x) + sqrt(x + y);
  const double v = value(x);
  return a / b + lift(x, D2{std::sin(v), std::cos(v), -std::sin(v)});
}

TEST(Jet, GivesTheSameGradientWithOrWithoutTheHessian) {
  for (double x0 : {0.3, 1.7, 12.0})
    for (double y0 : {0.05, 2.5}) {
      const Jet<2> with = every_operation(Jet<2>::variable(x0, 0), Jet<2>::variable(y0, 1));
      const Jet<2, 1> without = every_operation(Jet<2, 1>::variable(x0, 0), Jet<2, 1>::variable(y0, 1));
      EXPECT_EQ(with.v, without.v) << x0 << " " << y0;
      EXPECT_EQ(with.g(0), without.g(0)) << x0 << " " << y0;
      EXPECT_EQ(with.g(1), without.g(1)) << x0 << " " << y0;
      EXPECT_EQ(with.v, every_operation(x0, y0)) << "the value is the double formula's";
    }
  static_assert(sizeof(Jet<2, 1>) + 4 * sizeof(double) == sizeof(Jet<2>), "no room taken by the absent Hessian");
}

TEST(Jet, CarriesTheDerivativesOfTheFormulaToFiniteDifferenceAccuracy) {
  const double x0 = 1.7, y0 = 2.5, h = 1e-4;
  const Jet<2> j = every_operation(Jet<2>::variable(x0, 0), Jet<2>::variable(y0, 1));
  auto f = [](double x, double y) { return every_operation(x, y); };
  // Central differences: error O(h^2 f''') ~ 1e-8 for these smooth terms; 1e-6 leaves room.
  EXPECT_NEAR(j.g(0), (f(x0 + h, y0) - f(x0 - h, y0)) / (2 * h), 1e-6);
  EXPECT_NEAR(j.g(1), (f(x0, y0 + h) - f(x0, y0 - h)) / (2 * h), 1e-6);
  const double fxy = (f(x0 + h, y0 + h) - f(x0 + h, y0 - h) - f(x0 - h, y0 + h) + f(x0 - h, y0 - h)) / (4 * h * h);
  EXPECT_NEAR(j.h(0, 1), fxy, 1e-4);
  EXPECT_EQ(j.h(0, 1), j.h(1, 0));
}

}  // namespace
}  // namespace gmwm::internal
