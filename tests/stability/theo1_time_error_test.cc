// Theo1, MTIE and TIE rms (deviation.h; theo1.cc, time_error.cc) against Stable32's values for
// PHASE.DAT (NBS14's 1000-point set) at every averaging factor it lists, to the printed digits,
// and against their term-by-term definitions on random series; their factor sets and refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/stability/deviation.h"
#include "nbs14.h"

namespace gmwm::stability {
namespace {

using testing::phase_dat;

double printed_tolerance(double v) { return testing::printed_half_unit(v); }

// A row of Stable32's table: AF, "#" (Theo1's printed to 5 digits), the value.
struct Printed {
  std::int64_t m;
  double terms, sigma;
};

// Stable32 on PHASE.DAT.
// Theo1 (Alpha = 0: no bias correction), every AF Stable32 lists: AF, "Theo1 #", Theo1.
const std::vector<Printed> kTheo1 = {
    {10, 4.9550e+03, 1.0757e-01},  {12, 5.9340e+03, 9.8141e-02},  {14, 6.9090e+03, 9.0860e-02},
    {16, 7.8800e+03, 8.5040e-02},  {18, 8.8470e+03, 7.8842e-02},  {20, 9.8100e+03, 7.2762e-02},
    {22, 1.0769e+04, 6.7875e-02},  {24, 1.1724e+04, 6.4021e-02},  {26, 1.2675e+04, 6.1186e-02},
    {28, 1.3622e+04, 5.8311e-02},  {30, 1.4565e+04, 5.6096e-02},  {32, 1.5504e+04, 5.4258e-02},
    {34, 1.6439e+04, 5.2309e-02},  {36, 1.7370e+04, 5.0993e-02},  {38, 1.8297e+04, 4.9764e-02},
    {40, 1.9220e+04, 4.8652e-02},  {42, 2.0139e+04, 4.7643e-02},  {44, 2.1054e+04, 4.6830e-02},
    {46, 2.1965e+04, 4.6251e-02},  {48, 2.2872e+04, 4.5725e-02},  {50, 2.3775e+04, 4.4920e-02},
    {52, 2.4674e+04, 4.4024e-02},  {54, 2.5569e+04, 4.3036e-02},  {56, 2.6460e+04, 4.2210e-02},
    {58, 2.7347e+04, 4.1427e-02},  {60, 2.8230e+04, 4.0704e-02},  {62, 2.9109e+04, 4.0370e-02},
    {64, 2.9984e+04, 3.9799e-02},  {66, 3.0855e+04, 3.9297e-02},  {68, 3.1722e+04, 3.8744e-02},
    {70, 3.2585e+04, 3.8206e-02},  {72, 3.3444e+04, 3.7716e-02},  {74, 3.4299e+04, 3.7332e-02},
    {76, 3.5150e+04, 3.6970e-02},  {78, 3.5997e+04, 3.6320e-02},  {80, 3.6840e+04, 3.5718e-02},
    {82, 3.7679e+04, 3.5120e-02},  {84, 3.8514e+04, 3.4549e-02},  {86, 3.9345e+04, 3.4107e-02},
    {88, 4.0172e+04, 3.3769e-02},  {90, 4.0995e+04, 3.3422e-02},  {92, 4.1814e+04, 3.3138e-02},
    {94, 4.2629e+04, 3.2777e-02},  {96, 4.3440e+04, 3.2455e-02},  {98, 4.4247e+04, 3.2131e-02},
    {100, 4.5050e+04, 3.1789e-02}, {102, 4.5849e+04, 3.1635e-02}, {104, 4.6644e+04, 3.1422e-02},
    {106, 4.7435e+04, 3.1133e-02}, {108, 4.8222e+04, 3.0884e-02}, {110, 4.9005e+04, 3.0746e-02},
    {112, 4.9784e+04, 3.0625e-02}, {114, 5.0559e+04, 3.0510e-02}, {116, 5.1330e+04, 3.0301e-02},
    {118, 5.2097e+04, 3.0066e-02}, {120, 5.2860e+04, 2.9932e-02}, {122, 5.3619e+04, 2.9975e-02},
    {124, 5.4374e+04, 2.9933e-02}, {126, 5.5125e+04, 2.9982e-02}, {128, 5.5872e+04, 2.9963e-02},
    {130, 5.6615e+04, 2.9945e-02}, {132, 5.7354e+04, 2.9858e-02}, {134, 5.8089e+04, 2.9833e-02},
    {136, 5.8820e+04, 2.9781e-02}, {138, 5.9547e+04, 2.9742e-02}, {140, 6.0270e+04, 2.9673e-02},
    {142, 6.0989e+04, 2.9607e-02}, {146, 6.2415e+04, 2.9483e-02}, {150, 6.3825e+04, 2.9363e-02},
    {154, 6.5219e+04, 2.9033e-02}, {158, 6.6597e+04, 2.8770e-02}, {162, 6.7959e+04, 2.8393e-02},
    {166, 6.9305e+04, 2.7971e-02}, {170, 7.0635e+04, 2.7493e-02}, {174, 7.1949e+04, 2.7043e-02},
    {178, 7.3247e+04, 2.6687e-02}, {182, 7.4529e+04, 2.6232e-02}, {186, 7.5795e+04, 2.5583e-02},
    {190, 7.7045e+04, 2.5189e-02}, {194, 7.8279e+04, 2.4851e-02}, {198, 7.9497e+04, 2.4584e-02},
    {202, 8.0699e+04, 2.4120e-02}, {206, 8.1885e+04, 2.3689e-02}, {210, 8.3055e+04, 2.3322e-02},
    {214, 8.4209e+04, 2.3145e-02}, {218, 8.5347e+04, 2.2945e-02}, {222, 8.6469e+04, 2.2688e-02},
    {226, 8.7575e+04, 2.2333e-02}, {230, 8.8665e+04, 2.2081e-02}, {234, 8.9739e+04, 2.1973e-02},
    {238, 9.0797e+04, 2.1817e-02}, {242, 9.1839e+04, 2.1658e-02}, {246, 9.2865e+04, 2.1365e-02},
    {250, 9.3875e+04, 2.1112e-02}, {254, 9.4869e+04, 2.0858e-02}, {258, 9.5847e+04, 2.0704e-02},
    {262, 9.6809e+04, 2.0555e-02}, {266, 9.7755e+04, 2.0349e-02}, {270, 9.8685e+04, 2.0040e-02},
    {274, 9.9599e+04, 1.9731e-02}, {278, 1.0050e+05, 1.9486e-02}, {282, 1.0138e+05, 1.9266e-02},
    {286, 1.0225e+05, 1.9102e-02}, {292, 1.0351e+05, 1.8810e-02}, {298, 1.0475e+05, 1.8522e-02},
    {304, 1.0594e+05, 1.8092e-02}, {310, 1.0711e+05, 1.7806e-02}, {316, 1.0823e+05, 1.7508e-02},
    {322, 1.0932e+05, 1.7086e-02}, {328, 1.1037e+05, 1.6863e-02}, {334, 1.1139e+05, 1.6615e-02},
    {340, 1.1237e+05, 1.6267e-02}, {346, 1.1332e+05, 1.6010e-02}, {352, 1.1422e+05, 1.5627e-02},
    {358, 1.1510e+05, 1.5432e-02}, {364, 1.1593e+05, 1.5237e-02}, {370, 1.1674e+05, 1.4973e-02},
    {376, 1.1750e+05, 1.4781e-02}, {382, 1.1823e+05, 1.4739e-02}, {388, 1.1892e+05, 1.4599e-02},
    {394, 1.1958e+05, 1.4441e-02}, {400, 1.2020e+05, 1.4321e-02}, {406, 1.2079e+05, 1.4139e-02},
    {412, 1.2133e+05, 1.3942e-02}, {418, 1.2185e+05, 1.3844e-02}, {424, 1.2232e+05, 1.3693e-02},
    {430, 1.2277e+05, 1.3529e-02}, {438, 1.2330e+05, 1.3378e-02}, {446, 1.2377e+05, 1.3194e-02},
    {454, 1.2417e+05, 1.3011e-02}, {462, 1.2451e+05, 1.2903e-02}, {470, 1.2479e+05, 1.2934e-02},
    {478, 1.2500e+05, 1.2864e-02}, {486, 1.2515e+05, 1.2787e-02}, {494, 1.2523e+05, 1.2699e-02},
    {502, 1.2525e+05, 1.2626e-02}, {510, 1.2521e+05, 1.2503e-02}, {518, 1.2510e+05, 1.2298e-02},
    {526, 1.2493e+05, 1.2229e-02}, {534, 1.2469e+05, 1.2254e-02}, {542, 1.2439e+05, 1.2159e-02},
    {550, 1.2403e+05, 1.2100e-02}, {558, 1.2360e+05, 1.2092e-02}, {566, 1.2311e+05, 1.2015e-02},
    {574, 1.2255e+05, 1.1840e-02}, {584, 1.2176e+05, 1.1796e-02}, {594, 1.2088e+05, 1.1545e-02},
    {604, 1.1989e+05, 1.1356e-02}, {614, 1.1881e+05, 1.1196e-02}, {624, 1.1762e+05, 1.0970e-02},
    {634, 1.1634e+05, 1.0789e-02}, {644, 1.1495e+05, 1.0703e-02}, {654, 1.1347e+05, 1.0442e-02},
    {664, 1.1188e+05, 1.0164e-02}, {674, 1.1020e+05, 9.8959e-03}, {684, 1.0841e+05, 9.5713e-03},
    {694, 1.0653e+05, 9.4422e-03}, {704, 1.0454e+05, 9.1774e-03}, {714, 1.0246e+05, 8.8995e-03},
    {726, 9.9825e+04, 8.5610e-03}, {738, 9.7047e+04, 8.1255e-03}, {750, 9.4125e+04, 7.7735e-03},
    {762, 9.1059e+04, 7.5609e-03}, {774, 8.7849e+04, 7.6692e-03}, {786, 8.4495e+04, 8.1974e-03},
    {798, 8.0997e+04, 8.7719e-03}, {810, 7.7355e+04, 9.3005e-03}, {822, 7.3569e+04, 9.6578e-03},
    {834, 6.9639e+04, 9.9848e-03}, {846, 6.5565e+04, 1.0067e-02}, {858, 6.1347e+04, 1.0196e-02},
    {872, 5.6244e+04, 1.0146e-02}, {886, 5.0945e+04, 1.0080e-02}, {900, 4.5450e+04, 9.4996e-03},
    {914, 3.9759e+04, 8.6773e-03}, {928, 3.3872e+04, 7.9619e-03}, {942, 2.7789e+04, 7.7650e-03},
    {956, 2.1510e+04, 7.1337e-03}, {970, 1.5035e+04, 6.0725e-03}, {984, 8.3640e+03, 5.5184e-03},
    {998, 1.4970e+03, 5.0234e-03}};
// MTIE (Fast): AF, #, MTIE.
const std::vector<Printed> kMtie = {{1, 1000, 5.0597e-01},  {3, 998, 1.2984e+00},   {7, 994, 2.2922e+00},
                                    {15, 986, 2.9949e+00},  {31, 970, 4.4550e+00},  {63, 938, 6.5989e+00},
                                    {127, 874, 6.8061e+00}, {255, 746, 7.8205e+00}, {511, 490, 7.8205e+00}};
// TIE rms, every AF Stable32 lists: AF, #, TIE rms.
const std::vector<Printed> kTieRms = {
    {1, 1000, 2.8832e-01},  {2, 999, 4.0240e-01},   {3, 998, 4.9390e-01},   {4, 997, 5.7044e-01},
    {5, 996, 6.4195e-01},   {6, 995, 7.0066e-01},   {7, 994, 7.5338e-01},   {8, 993, 7.9644e-01},
    {9, 992, 8.3728e-01},   {10, 991, 8.7588e-01},  {11, 990, 9.0905e-01},  {12, 989, 9.4366e-01},
    {13, 988, 9.7453e-01},  {14, 987, 1.0048e+00},  {15, 986, 1.0312e+00},  {16, 985, 1.0573e+00},
    {17, 984, 1.0866e+00},  {18, 983, 1.1159e+00},  {19, 982, 1.1485e+00},  {20, 981, 1.1845e+00},
    {21, 980, 1.2213e+00},  {22, 979, 1.2576e+00},  {23, 978, 1.2949e+00},  {24, 977, 1.3306e+00},
    {25, 976, 1.3652e+00},  {26, 975, 1.3977e+00},  {27, 974, 1.4325e+00},  {28, 973, 1.4663e+00},
    {29, 972, 1.4980e+00},  {30, 971, 1.5293e+00},  {31, 970, 1.5578e+00},  {32, 969, 1.5871e+00},
    {33, 968, 1.6172e+00},  {34, 967, 1.6464e+00},  {35, 966, 1.6735e+00},  {36, 965, 1.7010e+00},
    {37, 964, 1.7267e+00},  {38, 963, 1.7528e+00},  {39, 962, 1.7784e+00},  {40, 961, 1.8023e+00},
    {41, 960, 1.8236e+00},  {42, 959, 1.8447e+00},  {43, 958, 1.8647e+00},  {44, 957, 1.8823e+00},
    {45, 956, 1.8975e+00},  {46, 955, 1.9124e+00},  {47, 954, 1.9269e+00},  {48, 953, 1.9424e+00},
    {49, 952, 1.9584e+00},  {50, 951, 1.9745e+00},  {51, 950, 1.9892e+00},  {52, 949, 2.0058e+00},
    {53, 948, 2.0237e+00},  {54, 947, 2.0421e+00},  {55, 946, 2.0615e+00},  {56, 945, 2.0791e+00},
    {57, 944, 2.0975e+00},  {58, 943, 2.1165e+00},  {59, 942, 2.1340e+00},  {60, 941, 2.1533e+00},
    {61, 940, 2.1705e+00},  {62, 939, 2.1855e+00},  {63, 938, 2.2014e+00},  {64, 937, 2.2171e+00},
    {65, 936, 2.2326e+00},  {66, 935, 2.2484e+00},  {67, 934, 2.2631e+00},  {68, 933, 2.2808e+00},
    {69, 932, 2.2979e+00},  {70, 931, 2.3151e+00},  {71, 930, 2.3318e+00},  {73, 928, 2.3638e+00},
    {75, 926, 2.3943e+00},  {77, 924, 2.4250e+00},  {79, 922, 2.4578e+00},  {81, 920, 2.4894e+00},
    {83, 918, 2.5216e+00},  {85, 916, 2.5523e+00},  {87, 914, 2.5843e+00},  {89, 912, 2.6113e+00},
    {91, 910, 2.6380e+00},  {93, 908, 2.6637e+00},  {95, 906, 2.6899e+00},  {97, 904, 2.7128e+00},
    {99, 902, 2.7366e+00},  {101, 900, 2.7603e+00}, {103, 898, 2.7772e+00}, {105, 896, 2.7980e+00},
    {107, 894, 2.8162e+00}, {109, 892, 2.8344e+00}, {111, 890, 2.8493e+00}, {113, 888, 2.8651e+00},
    {115, 886, 2.8804e+00}, {117, 884, 2.9004e+00}, {119, 882, 2.9159e+00}, {121, 880, 2.9271e+00},
    {123, 878, 2.9353e+00}, {125, 876, 2.9422e+00}, {127, 874, 2.9484e+00}, {129, 872, 2.9520e+00},
    {131, 870, 2.9566e+00}, {133, 868, 2.9611e+00}, {135, 866, 2.9601e+00}, {137, 864, 2.9600e+00},
    {139, 862, 2.9568e+00}, {141, 860, 2.9518e+00}, {143, 858, 2.9475e+00}, {146, 855, 2.9418e+00},
    {149, 852, 2.9344e+00}, {152, 849, 2.9303e+00}, {155, 846, 2.9273e+00}, {158, 843, 2.9162e+00},
    {161, 840, 2.9056e+00}, {164, 837, 2.8988e+00}, {167, 834, 2.8901e+00}, {170, 831, 2.8823e+00},
    {173, 828, 2.8761e+00}, {176, 825, 2.8727e+00}, {179, 822, 2.8651e+00}, {182, 819, 2.8575e+00},
    {185, 816, 2.8560e+00}, {188, 813, 2.8502e+00}, {191, 810, 2.8441e+00}, {194, 807, 2.8365e+00},
    {197, 804, 2.8261e+00}, {200, 801, 2.8163e+00}, {203, 798, 2.8046e+00}, {206, 795, 2.7965e+00},
    {209, 792, 2.7916e+00}, {212, 789, 2.7835e+00}, {215, 786, 2.7681e+00}, {219, 782, 2.7490e+00},
    {223, 778, 2.7337e+00}, {227, 774, 2.7264e+00}, {231, 770, 2.7118e+00}, {235, 766, 2.6886e+00},
    {239, 762, 2.6623e+00}, {243, 758, 2.6373e+00}, {247, 754, 2.6144e+00}};

// The rows' values, "#" and tau from `kind` on PHASE.DAT, to the digits Stable32 prints.
void expect_rows(DeviationKind kind, const std::vector<Printed>& rows, double tau_per_factor) {
  const std::vector<double> x = phase_dat();
  std::vector<std::int64_t> m;
  for (const Printed& r : rows) m.push_back(r.m);
  const DeviationCurve c = deviation(kind, x, 1.0, m);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::string what = std::string(deviation_name(kind)) + " AF " + std::to_string(rows[k].m);
    EXPECT_NEAR(c.value[k], rows[k].sigma, printed_tolerance(rows[k].sigma)) << what;
    EXPECT_NEAR(static_cast<double>(c.terms[k]), rows[k].terms, printed_tolerance(rows[k].terms)) << what;
    EXPECT_DOUBLE_EQ(c.tau[k], tau_per_factor * static_cast<double>(rows[k].m)) << what;
  }
}

TEST(Theo1, MatchesStable32sPlainTheo1OnPhaseDatAtEveryFactorItLists) {
  // Stable32's Theo1 told "Alpha = 0" applies no bias correction (white FM's is 1): the plain
  // Theo1, at tau = 0.75 m, over (N - m) m / 2 terms.
  expect_rows(DeviationKind::kTheo1, kTheo1, 0.75);
}

// NIST SP 1065 eq. 30 as written: sum over i and delta = 0 .. m/2 - 1 of the squared
// (x_i - x_{i-delta+m/2}) + (x_{i+m} - x_{i+delta+m/2}), weighted 1 / (m/2 - delta).
double literal_theo1(const std::vector<double>& x, std::int64_t m, double tau0) {
  const auto n = static_cast<std::int64_t>(x.size());
  long double sum = 0.0L;
  for (std::int64_t i = 0; i < n - m; ++i)
    for (std::int64_t delta = 0; delta < m / 2; ++delta) {
      const auto at = [&](std::int64_t j) { return x[static_cast<std::size_t>(j)]; };
      const double d = (at(i) - at(i - delta + m / 2)) + (at(i + m) - at(i + delta + m / 2));
      sum += d * d / static_cast<double>(m / 2 - delta);
    }
  const double tau = static_cast<double>(m) * tau0;
  return std::sqrt(static_cast<double>(sum) / (0.75 * static_cast<double>(n - m) * tau * tau));
}

// White, random-walk and integrated random-walk phase with an offset and a frequency offset.
std::vector<std::vector<double>> random_phases(std::size_t n) {
  std::mt19937_64 rng(30);
  std::normal_distribution<double> normal;
  std::vector<std::vector<double>> out(3, std::vector<double>(n));
  double walk = 0.0, integrated = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = normal(rng);
    walk += w;
    integrated += walk;
    const double line = 1e3 + 0.25 * static_cast<double>(i);
    out[0][i] = w + line;
    out[1][i] = walk + line;
    out[2][i] = integrated / 30.0 + line;
  }
  return out;
}

TEST(Theo1, EqualsItsDefinitionOnRandomSeries) {
  // Factors summed term by term (m <= 128) and through correlations (beyond), up to N - 1.
  const std::vector<std::int64_t> m = {10, 12, 64, 128, 130, 200, 258, 600, 1000, 1198};
  for (const std::vector<double>& x : random_phases(1200)) {
    const DeviationCurve c = deviation(DeviationKind::kTheo1, x, 0.5, m);
    for (std::size_t k = 0; k < m.size(); ++k)
      EXPECT_NEAR(c.value[k] / literal_theo1(x, m[k], 0.5), 1.0, 1e-10) << "m " << m[k];
  }
}

TEST(Theo1, ReadsTheEvenFactorsFromTenAtThreeQuartersOfTheirTime) {
  EXPECT_EQ(min_phase_points(DeviationKind::kTheo1), 11);
  EXPECT_EQ(max_factor(DeviationKind::kTheo1, 10), 0);
  EXPECT_EQ(max_factor(DeviationKind::kTheo1, 1001), 1000);
  EXPECT_EQ(max_factor(DeviationKind::kTheo1, 1000), 998);
  EXPECT_EQ(terms(DeviationKind::kTheo1, 1001, 1000), 500);
  EXPECT_EQ(factors(TauSet::kOctave, DeviationKind::kTheo1, 1001),
            (std::vector<std::int64_t>{10, 20, 40, 80, 160, 320, 640}));
  EXPECT_EQ(factors(TauSet::kDecade, DeviationKind::kTheo1, 1001),
            (std::vector<std::int64_t>{10, 20, 40, 100, 200, 400, 1000}));
  const std::vector<std::int64_t> all = factors(TauSet::kAll, DeviationKind::kTheo1, 1001);
  EXPECT_EQ(all.size(), 496u);
  EXPECT_EQ(all.front(), 10);
  EXPECT_EQ(all.back(), 1000);
  EXPECT_DOUBLE_EQ(averaging_time(DeviationKind::kTheo1, 10, 0.01), 0.075);
  const std::vector<double> x = phase_dat();
  for (const std::int64_t bad : {8, 11, 1002}) {
    try {
      const std::vector<std::int64_t> m = {bad};
      deviation(DeviationKind::kTheo1, x, 1.0, m);
      FAIL() << "took factor " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), "theo1: averaging factor " + std::to_string(bad) +
                                           " is outside the even factors 10 .. 1000 (1001 phase points)");
    }
  }
  try {
    const std::vector<std::int64_t> m = {10};
    deviation(DeviationKind::kTheo1, std::span<const double>(x).first(10), 1.0, m);
    FAIL() << "took 10 phase points";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "theo1: found 10 phase points, expected at least 11");
  }
}

TEST(TimeError, MtieMatchesStable32OnPhaseDatOverWindowsOfTwoToTheKPoints) {
  // Stable32's AF m reads windows of m + 1 points (N - m of them, its "#"); its octaves are
  // the windows of 2^k points, which factors(kOctave) gives MTIE.
  expect_rows(DeviationKind::kMtie, kMtie, 1.0);
  std::vector<std::int64_t> listed;
  for (const Printed& r : kMtie) listed.push_back(r.m);
  EXPECT_EQ(factors(TauSet::kOctave, DeviationKind::kMtie, 1001), listed);
}

TEST(TimeError, TieRmsMatchesStable32OnPhaseDatAtEveryFactorItLists) {
  expect_rows(DeviationKind::kTierms, kTieRms, 1.0);
}

TEST(TimeError, MtieAndTieRmsEqualTheirDefinitionsOnRandomSeries) {
  for (const std::vector<double>& x : random_phases(401)) {
    const auto n = static_cast<std::int64_t>(x.size());
    const std::vector<std::int64_t> m = factors(TauSet::kAll, DeviationKind::kMtie, n);
    const DeviationCurve mtie = deviation(DeviationKind::kMtie, x, 1.0, m);
    const DeviationCurve rms = deviation(DeviationKind::kTierms, x, 1.0, m);
    for (std::size_t k = 0; k < m.size(); ++k) {
      double largest = 0.0, squares = 0.0;
      for (std::int64_t i = 0; i + m[k] < n; ++i) {
        const auto first = x.begin() + i, last = x.begin() + i + m[k] + 1;
        largest = std::max(largest, *std::max_element(first, last) - *std::min_element(first, last));
        const double d = x[static_cast<std::size_t>(i + m[k])] - x[static_cast<std::size_t>(i)];
        squares += d * d;
      }
      ASSERT_EQ(mtie.value[k], largest) << "m " << m[k];
      EXPECT_NEAR(rms.value[k] / std::sqrt(squares / static_cast<double>(n - m[k])), 1.0, 1e-12) << "m " << m[k];
      EXPECT_EQ(mtie.terms[k], n - m[k]);
    }
  }
  EXPECT_EQ(max_factor(DeviationKind::kMtie, 2), 1);
  EXPECT_EQ(max_factor(DeviationKind::kTierms, 1), 0);
  EXPECT_TRUE(in_time_units(DeviationKind::kMtie) && in_time_units(DeviationKind::kTierms));
  EXPECT_FALSE(in_time_units(DeviationKind::kTheo1));
}

}  // namespace
}  // namespace gmwm::stability
