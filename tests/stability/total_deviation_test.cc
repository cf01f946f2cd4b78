// The modified, time and Hadamard total deviations (deviation.h, total_deviation.cc) against
// Stable32's values for PHASE.DAT (NBS14's 1000-point set): its octave and decade tables to the
// printed digits, the rows it printed flagged '#' too; its all-AF tables (Stable32 1.53), which
// divide each variance by the bias factor of the noise it identified, to a unit of the last
// digit once that published two-digit factor is divided out; the Hadamard total with and
// without its bias correction; and their window-by-window definition on random series.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "gmwm/stability/deviation.h"
#include "nbs14.h"

namespace gmwm::stability {
namespace {

using testing::phase_dat;

double printed_tolerance(double v) { return testing::printed_half_unit(v); }

// A row of Stable32's table: AF, "#", the noise exponent alpha it identified, the deviation.
struct Row {
  std::int64_t m, terms;
  int alpha;
  double sigma;
};

// Stable32 1.60 on PHASE.DAT (the rows from AF 32 of the octave tables printed flagged '#').
const std::vector<Row> kMtotOctave = {{1, 999, 0, 2.0664e-01},  {2, 996, 0, 1.4337e-01},   {4, 990, 0, 9.4613e-02},
                                      {8, 978, 0, 6.5721e-02},  {16, 954, 0, 3.7135e-02},  {32, 906, 0, 2.9114e-02},
                                      {64, 810, 0, 2.3606e-02}, {128, 618, 1, 1.6668e-02}, {256, 234, 1, 5.9607e-03}};
const std::vector<Row> kMtotDecade = {{1, 999, 0, 2.0664e-01},   {2, 996, 0, 1.4337e-01},  {4, 990, 0, 9.4613e-02},
                                      {10, 972, 0, 5.5529e-02},  {20, 942, 0, 3.3114e-02}, {40, 882, 0, 2.6852e-02},
                                      {100, 702, 1, 1.9547e-02}, {200, 402, 1, 8.4842e-03}};
const std::vector<Row> kTtotOctave = {{1, 999, 0, 1.1930e-01},  {2, 996, 0, 1.6555e-01},   {4, 990, 0, 2.1850e-01},
                                      {8, 978, 0, 3.0355e-01},  {16, 954, 0, 3.4304e-01},  {32, 906, 0, 5.3788e-01},
                                      {64, 810, 0, 8.7227e-01}, {128, 618, 1, 1.2318e+00}, {256, 234, 1, 8.8101e-01}};
const std::vector<Row> kTtotDecade = {{1, 999, 0, 1.1930e-01},   {2, 996, 0, 1.6555e-01},  {4, 990, 0, 2.1850e-01},
                                      {10, 972, 0, 3.2060e-01},  {20, 942, 0, 3.8237e-01}, {40, 882, 0, 6.2013e-01},
                                      {100, 702, 1, 1.1285e+00}, {200, 402, 1, 9.7967e-01}};
// Stable32 on the 1000-point frequency set, Hadamard Total, bias correction off (alpha: the
// one it was told, unused) and on (alpha: the one it identified).
const std::vector<Row> kHtotPlain = {{1, 998, 2, 2.9439e-01},  {2, 995, 2, 2.0247e-01},   {4, 989, 2, 1.4216e-01},
                                     {8, 977, 2, 1.0795e-01},  {16, 953, 2, 6.5102e-02},  {32, 905, 2, 4.4532e-02},
                                     {64, 809, 2, 3.3492e-02}, {128, 617, 2, 2.8790e-02}, {256, 233, 2, 1.4773e-02}};
const std::vector<Row> kHtotCorrected = {
    {1, 998, 0, 2.9439e-01},  {2, 995, 0, 2.0297e-01},   {4, 989, 0, 1.4252e-01},
    {8, 977, 0, 1.0822e-01},  {16, 953, 0, 6.5265e-02},  {32, 905, 0, 4.4644e-02},
    {64, 809, 0, 3.3576e-02}, {128, 617, 1, 2.8790e-02}, {256, 233, 1, 1.4773e-02}};
// Stable32 1.53, Modified Total, every AF it lists (158 rows; its alpha, the bias divided by).
const std::vector<Row> kMtot153 = {
    {1, 999, 0, 2.4185e-01},   {2, 996, 0, 1.6780e-01},   {3, 993, 0, 1.2701e-01},   {4, 990, 0, 1.1074e-01},
    {5, 987, 0, 9.9581e-02},   {6, 984, 0, 9.1043e-02},   {7, 981, 0, 8.3596e-02},   {8, 978, 0, 7.6921e-02},
    {9, 975, 0, 7.0655e-02},   {10, 972, 0, 6.4992e-02},  {11, 969, 0, 5.9849e-02},  {12, 966, 0, 5.5410e-02},
    {13, 963, 0, 5.1608e-02},  {14, 960, 0, 4.8429e-02},  {15, 957, 0, 4.5714e-02},  {16, 954, 0, 4.3463e-02},
    {17, 951, 0, 4.1711e-02},  {18, 948, 0, 4.0421e-02},  {19, 945, 0, 3.9470e-02},  {20, 942, 0, 3.8758e-02},
    {21, 939, 0, 3.8190e-02},  {22, 936, 0, 3.7739e-02},  {23, 933, 0, 3.7360e-02},  {24, 930, 0, 3.7011e-02},
    {25, 927, 0, 3.6662e-02},  {26, 924, 0, 3.6313e-02},  {27, 921, 0, 3.5954e-02},  {28, 918, 0, 3.5601e-02},
    {29, 915, 0, 3.5243e-02},  {30, 912, 0, 3.4867e-02},  {31, 909, 0, 3.4467e-02},  {32, 906, 0, 3.4075e-02},
    {33, 903, 0, 3.3695e-02},  {34, 900, 0, 3.3336e-02},  {35, 897, 0, 3.2988e-02},  {36, 894, 0, 3.2648e-02},
    {37, 891, 0, 3.2318e-02},  {38, 888, 0, 3.2007e-02},  {39, 885, 0, 3.1710e-02},  {40, 882, 0, 3.1428e-02},
    {41, 879, 0, 3.1161e-02},  {42, 876, 0, 3.0911e-02},  {43, 873, 0, 3.0674e-02},  {44, 870, 0, 3.0452e-02},
    {45, 867, 0, 3.0243e-02},  {46, 864, 0, 3.0049e-02},  {47, 861, 0, 2.9869e-02},  {48, 858, 0, 2.9703e-02},
    {49, 855, 0, 2.9551e-02},  {50, 852, 0, 2.9409e-02},  {51, 849, 0, 2.9276e-02},  {52, 846, 0, 2.9147e-02},
    {53, 843, 0, 2.9024e-02},  {54, 840, 0, 2.8905e-02},  {55, 837, 0, 2.8788e-02},  {56, 834, 0, 2.8672e-02},
    {57, 831, 0, 2.8553e-02},  {58, 828, 0, 2.8431e-02},  {59, 825, 0, 2.8307e-02},  {60, 822, 0, 2.8182e-02},
    {61, 819, 0, 2.8052e-02},  {62, 816, 0, 2.7917e-02},  {63, 813, 0, 2.7773e-02},  {64, 810, 0, 2.7629e-02},
    {65, 807, 0, 2.7487e-02},  {66, 804, 0, 2.7347e-02},  {67, 801, 0, 2.7205e-02},  {68, 798, 0, 2.7057e-02},
    {69, 795, 1, 2.5230e-02},  {70, 792, 1, 2.5084e-02},  {71, 789, 1, 2.4938e-02},  {73, 783, 0, 2.6290e-02},
    {75, 777, 0, 2.5998e-02},  {77, 771, 0, 2.5709e-02},  {79, 765, 0, 2.5429e-02},  {81, 759, 0, 2.5161e-02},
    {83, 753, 1, 2.3357e-02},  {85, 747, 0, 2.4656e-02},  {87, 741, 1, 2.2893e-02},  {89, 735, 1, 2.2668e-02},
    {91, 729, 0, 2.3934e-02},  {93, 723, 0, 2.3696e-02},  {95, 717, 0, 2.3460e-02},  {97, 711, 0, 2.3227e-02},
    {99, 705, 1, 2.1565e-02},  {101, 699, 1, 2.1346e-02}, {103, 693, 1, 2.1126e-02}, {105, 687, 0, 2.2291e-02},
    {107, 681, 1, 2.0683e-02}, {109, 675, 1, 2.0461e-02}, {111, 669, 1, 2.0237e-02}, {113, 663, 0, 2.1337e-02},
    {115, 657, 0, 2.1093e-02}, {117, 651, 0, 2.0846e-02}, {119, 645, 0, 2.0601e-02}, {121, 639, 0, 2.0357e-02},
    {123, 633, 1, 1.8864e-02}, {125, 627, 1, 1.8637e-02}, {127, 621, 1, 1.8410e-02}, {129, 615, 1, 1.8181e-02},
    {131, 609, 1, 1.7949e-02}, {133, 603, 1, 1.7712e-02}, {135, 597, 1, 1.7472e-02}, {137, 591, 1, 1.7228e-02},
    {139, 585, 1, 1.6979e-02}, {141, 579, 1, 1.6725e-02}, {143, 573, 1, 1.6465e-02}, {146, 564, 1, 1.6063e-02},
    {149, 555, 0, 1.6689e-02}, {152, 546, 1, 1.5234e-02}, {155, 537, 0, 1.5787e-02}, {158, 528, 0, 1.5327e-02},
    {161, 519, 0, 1.4875e-02}, {164, 510, 0, 1.4426e-02}, {167, 501, 0, 1.3982e-02}, {170, 492, 0, 1.3547e-02},
    {173, 483, 0, 1.3118e-02}, {176, 474, 0, 1.2699e-02}, {179, 465, 0, 1.2291e-02}, {182, 456, 0, 1.1899e-02},
    {185, 447, 0, 1.1526e-02}, {188, 438, 0, 1.1168e-02}, {191, 429, 0, 1.0830e-02}, {194, 420, 0, 1.0510e-02},
    {197, 411, 0, 1.0211e-02}, {200, 402, 0, 9.9300e-03}, {203, 393, 0, 9.6649e-03}, {206, 384, 0, 9.4139e-03},
    {209, 375, 0, 9.1770e-03}, {212, 366, 0, 8.9546e-03}, {215, 357, 0, 8.7470e-03}, {219, 345, 0, 8.4943e-03},
    {223, 333, 0, 8.2697e-03}, {227, 321, 0, 8.0710e-03}, {231, 309, 0, 7.8931e-03}, {235, 297, 0, 7.7343e-03},
    {239, 285, 0, 7.5909e-03}, {243, 273, 0, 7.4549e-03}, {247, 261, 0, 7.3156e-03}, {251, 249, 0, 7.1699e-03},
    {255, 237, 0, 7.0151e-03}, {259, 225, 0, 6.8627e-03}, {263, 213, 0, 6.7172e-03}, {267, 201, 0, 6.5758e-03},
    {271, 189, 0, 6.4272e-03}, {275, 177, 0, 6.2734e-03}, {279, 165, 0, 6.1208e-03}, {283, 153, 0, 5.9754e-03},
    {287, 141, 0, 5.8546e-03}, {292, 126, 0, 5.7454e-03}, {297, 111, 0, 5.6729e-03}, {302, 96, 0, 5.6058e-03},
    {307, 81, 0, 5.5206e-03},  {312, 66, 0, 5.4199e-03},  {317, 51, 0, 5.3241e-03},  {322, 36, 0, 5.1887e-03},
    {327, 21, 0, 4.9619e-03},  {332, 6, 0, 4.6727e-03}};
// Stable32 1.53, Time Total, every AF it lists (158 rows).
const std::vector<Row> kTtot153 = {
    {1, 999, 0, 1.3963e-01},   {2, 996, 0, 1.9376e-01},   {3, 993, 0, 2.1998e-01},   {4, 990, 0, 2.5573e-01},
    {5, 987, 0, 2.8747e-01},   {6, 984, 0, 3.1538e-01},   {7, 981, 0, 3.3785e-01},   {8, 978, 0, 3.5528e-01},
    {9, 975, 0, 3.6714e-01},   {10, 972, 0, 3.7523e-01},  {11, 969, 0, 3.8009e-01},  {12, 966, 0, 3.8389e-01},
    {13, 963, 0, 3.8734e-01},  {14, 960, 0, 3.9144e-01},  {15, 957, 0, 3.9589e-01},  {16, 954, 0, 4.0150e-01},
    {17, 951, 0, 4.0939e-01},  {18, 948, 0, 4.2007e-01},  {19, 945, 0, 4.3297e-01},  {20, 942, 0, 4.4753e-01},
    {21, 939, 0, 4.6302e-01},  {22, 936, 0, 4.7935e-01},  {23, 933, 0, 4.9610e-01},  {24, 930, 0, 5.1283e-01},
    {25, 927, 0, 5.2918e-01},  {26, 924, 0, 5.4510e-01},  {27, 921, 0, 5.6047e-01},  {28, 918, 0, 5.7551e-01},
    {29, 915, 0, 5.9009e-01},  {30, 912, 0, 6.0391e-01},  {31, 909, 0, 6.1689e-01},  {32, 906, 0, 6.2954e-01},
    {33, 903, 0, 6.4197e-01},  {34, 900, 0, 6.5438e-01},  {35, 897, 0, 6.6659e-01},  {36, 894, 0, 6.7857e-01},
    {37, 891, 0, 6.9038e-01},  {38, 888, 0, 7.0220e-01},  {39, 885, 0, 7.1401e-01},  {40, 882, 0, 7.2580e-01},
    {41, 879, 0, 7.3763e-01},  {42, 876, 0, 7.4955e-01},  {43, 873, 0, 7.6151e-01},  {44, 870, 0, 7.7358e-01},
    {45, 867, 0, 7.8573e-01},  {46, 864, 0, 7.9804e-01},  {47, 861, 0, 8.1050e-01},  {48, 858, 0, 8.2317e-01},
    {49, 855, 0, 8.3600e-01},  {50, 852, 0, 8.4898e-01},  {51, 849, 0, 8.6202e-01},  {52, 846, 0, 8.7507e-01},
    {53, 843, 0, 8.8813e-01},  {54, 840, 0, 9.0116e-01},  {55, 837, 0, 9.1414e-01},  {56, 834, 0, 9.2700e-01},
    {57, 831, 0, 9.3964e-01},  {58, 828, 0, 9.5206e-01},  {59, 825, 0, 9.6425e-01},  {60, 822, 0, 9.7626e-01},
    {61, 819, 0, 9.8796e-01},  {62, 816, 0, 9.9929e-01},  {63, 813, 0, 1.0102e+00},  {64, 810, 0, 1.0209e+00},
    {65, 807, 0, 1.0315e+00},  {66, 804, 0, 1.0421e+00},  {67, 801, 0, 1.0524e+00},  {68, 798, 0, 1.0622e+00},
    {69, 795, 1, 1.0051e+00},  {70, 792, 1, 1.0137e+00},  {71, 789, 1, 1.0223e+00},  {73, 783, 0, 1.1080e+00},
    {75, 777, 0, 1.1258e+00},  {77, 771, 0, 1.1429e+00},  {79, 765, 0, 1.1598e+00},  {81, 759, 0, 1.1767e+00},
    {83, 753, 1, 1.1193e+00},  {85, 747, 0, 1.2100e+00},  {87, 741, 1, 1.1499e+00},  {89, 735, 1, 1.1648e+00},
    {91, 729, 0, 1.2575e+00},  {93, 723, 0, 1.2723e+00},  {95, 717, 0, 1.2867e+00},  {97, 711, 0, 1.3008e+00},
    {99, 705, 1, 1.2326e+00},  {101, 699, 1, 1.2447e+00}, {103, 693, 1, 1.2563e+00}, {105, 687, 0, 1.3513e+00},
    {107, 681, 1, 1.2777e+00}, {109, 675, 1, 1.2876e+00}, {111, 669, 1, 1.2969e+00}, {113, 663, 0, 1.3920e+00},
    {115, 657, 0, 1.4005e+00}, {117, 651, 0, 1.4082e+00}, {119, 645, 0, 1.4154e+00}, {121, 639, 0, 1.4221e+00},
    {123, 633, 1, 1.3396e+00}, {125, 627, 1, 1.3450e+00}, {127, 621, 1, 1.3499e+00}, {129, 615, 1, 1.3541e+00},
    {131, 609, 1, 1.3575e+00}, {133, 603, 1, 1.3601e+00}, {135, 597, 1, 1.3618e+00}, {137, 591, 1, 1.3627e+00},
    {139, 585, 1, 1.3626e+00}, {141, 579, 1, 1.3615e+00}, {143, 573, 1, 1.3594e+00}, {146, 564, 1, 1.3540e+00},
    {149, 555, 0, 1.4357e+00}, {152, 546, 1, 1.3369e+00}, {155, 537, 0, 1.4128e+00}, {158, 528, 0, 1.3981e+00},
    {161, 519, 0, 1.3827e+00}, {164, 510, 0, 1.3659e+00}, {167, 501, 0, 1.3481e+00}, {170, 492, 0, 1.3296e+00},
    {173, 483, 0, 1.3103e+00}, {176, 474, 0, 1.2904e+00}, {179, 465, 0, 1.2702e+00}, {182, 456, 0, 1.2503e+00},
    {185, 447, 0, 1.2311e+00}, {188, 438, 0, 1.2122e+00}, {191, 429, 0, 1.1942e+00}, {194, 420, 0, 1.1772e+00},
    {197, 411, 0, 1.1614e+00}, {200, 402, 0, 1.1466e+00}, {203, 393, 0, 1.1327e+00}, {206, 384, 0, 1.1196e+00},
    {209, 375, 0, 1.1073e+00}, {212, 366, 0, 1.0960e+00}, {215, 357, 0, 1.0858e+00}, {219, 345, 0, 1.0740e+00},
    {223, 333, 0, 1.0647e+00}, {227, 321, 0, 1.0578e+00}, {231, 309, 0, 1.0527e+00}, {235, 297, 0, 1.0494e+00},
    {239, 285, 0, 1.0474e+00}, {243, 273, 0, 1.0459e+00}, {247, 261, 0, 1.0433e+00}, {251, 249, 0, 1.0390e+00},
    {255, 237, 0, 1.0328e+00}, {259, 225, 0, 1.0262e+00}, {263, 213, 0, 1.0200e+00}, {267, 201, 0, 1.0137e+00},
    {271, 189, 0, 1.0056e+00}, {275, 177, 0, 9.9603e-01}, {279, 165, 0, 9.8595e-01}, {283, 153, 0, 9.7632e-01},
    {287, 141, 0, 9.7011e-01}, {292, 126, 0, 9.6859e-01}, {297, 111, 0, 9.7275e-01}, {302, 96, 0, 9.7743e-01},
    {307, 81, 0, 9.7851e-01},  {312, 66, 0, 9.7630e-01},  {317, 51, 0, 9.7441e-01},  {322, 36, 0, 9.6461e-01},
    {327, 21, 0, 9.3677e-01},  {332, 6, 0, 8.9567e-01}};

// Stable32's bias factors, variance over its unbiased value by noise exponent alpha (W. J.
// Riley, "Confidence intervals and bias corrections for the Stable32 variance functions",
// Hamilton Technical Services, table of MTOT and HTOT bias): MTOT white PM 0.94, flicker PM
// 0.83, white FM 0.73, flicker FM 0.70, random-walk FM 0.69; HTOT white FM 0.995 (flicker FM
// 0.851, random-walk FM 0.771; none for PM noise, and none at m = 1, which is OHDEV).
const std::map<int, double> kMtotBias = {{2, 0.94}, {1, 0.83}, {0, 0.73}, {-1, 0.70}, {-2, 0.69}};
const std::map<int, double> kHtotBias = {{0, 0.995}, {-1, 0.851}, {-2, 0.771}};

// Each row's deviation and "#" from `kind` on PHASE.DAT, the deviation divided by the square
// root of `bias(row)`, to `units` of the last printed digit.
template <class Bias>
void expect_rows(DeviationKind kind, const std::vector<Row>& rows, Bias bias, double units, const std::string& what) {
  const std::vector<double> x = phase_dat();
  std::vector<std::int64_t> m;
  for (const Row& r : rows) m.push_back(r.m);
  const DeviationCurve c = deviation(kind, x, 1.0, m);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double corrected = c.value[k] / std::sqrt(bias(rows[k]));
    EXPECT_NEAR(corrected, rows[k].sigma, 2.0 * units * printed_tolerance(rows[k].sigma))
        << what << " AF " << rows[k].m;
    EXPECT_EQ(c.terms[k], rows[k].terms) << what << " AF " << rows[k].m;
    EXPECT_EQ(c.tau[k], static_cast<double>(rows[k].m)) << what;
  }
}
const auto kPlain = [](const Row&) { return 1.0; };

TEST(TotalDeviations, MatchStable32OnPhaseDatAtEveryOctaveAndDecade) {
  expect_rows(DeviationKind::kMtotdev, kMtotOctave, kPlain, 0.5, "mtotdev octave");
  expect_rows(DeviationKind::kMtotdev, kMtotDecade, kPlain, 0.5, "mtotdev decade");
  expect_rows(DeviationKind::kTtotdev, kTtotOctave, kPlain, 0.5, "ttotdev octave");
  expect_rows(DeviationKind::kTtotdev, kTtotDecade, kPlain, 0.5, "ttotdev decade");
  expect_rows(DeviationKind::kHtotdev, kHtotPlain, kPlain, 0.5, "htotdev without bias correction");
}

TEST(TotalDeviations, MatchStable32sBiasCorrectedTablesOnceTheirFactorIsDividedOut) {
  // Stable32 1.53's every-AF tables divide MTOTVAR by the factor of the noise it identified
  // (alpha 0 or 1 here): 1.17 and 1.10 times the plain deviation. The factors are published to
  // two digits, so the corrected values agree to a unit of the last digit (most to half).
  const auto mtot = [](const Row& r) { return kMtotBias.at(r.alpha); };
  expect_rows(DeviationKind::kMtotdev, kMtot153, mtot, 1.0, "mtotdev 1.53");
  expect_rows(DeviationKind::kTtotdev, kTtot153, mtot, 1.0, "ttotdev 1.53");
  // Its Hadamard total with bias correction: white FM (alpha 0) divided by 0.995 from m = 2;
  // none at m = 1 (OHDEV) nor for PM noise (alpha 1).
  const auto htot = [](const Row& r) { return r.m == 1 || r.alpha > 0 ? 1.0 : kHtotBias.at(r.alpha); };
  expect_rows(DeviationKind::kHtotdev, kHtotCorrected, htot, 0.5, "htotdev with bias correction");
}

// The window-by-window definition (NIST SP 1065 eq. 27, as allantools and Stable32's MTC.c read
// it): each window of 3m points of z less its half-average slope, reflected evenly at both ends
// to 9m points, the mean square of its 6m second differences of m-point averages; the mean of
// that over the windows.
double literal_total(const std::vector<double>& z, std::int64_t m) {
  const auto span = 3 * m, windows = static_cast<std::int64_t>(z.size()) - span + 1;
  const std::int64_t first_half = span / 2, second = (span + 1) / 2;
  const double distance = span % 2 == 1 ? static_cast<double>((span - 1) / 2 + 1) : static_cast<double>(span / 2);
  long double total = 0.0L;
  for (std::int64_t n = 0; n < windows; ++n) {
    double mean1 = 0.0, mean2 = 0.0;
    for (std::int64_t i = 0; i < first_half; ++i)
      mean1 += z[static_cast<std::size_t>(n + i)] / static_cast<double>(first_half);
    for (std::int64_t i = second; i < span; ++i)
      mean2 += z[static_cast<std::size_t>(n + i)] / static_cast<double>(span - second);
    const double slope = (mean2 - mean1) / distance;
    std::vector<double> u, e;
    for (std::int64_t i = 0; i < span; ++i)
      u.push_back(z[static_cast<std::size_t>(n + i)] - slope * static_cast<double>(i));
    e.insert(e.end(), u.rbegin(), u.rend());
    e.insert(e.end(), u.begin(), u.end());
    e.insert(e.end(), u.rbegin(), u.rend());
    double s1 = 0.0, s2 = 0.0, s3 = 0.0, squares = 0.0;
    for (std::int64_t k = 0; k < m; ++k) s1 += e[k], s2 += e[k + m], s3 += e[k + 2 * m];
    for (std::int64_t j = 0; j < 6 * m; ++j) {
      if (j > 0) {
        s1 += e[j + m - 1] - e[j - 1];
        s2 += e[j + 2 * m - 1] - e[j + m - 1];
        s3 += e[j + 3 * m - 1] - e[j + 2 * m - 1];
      }
      const double d = (s1 - 2.0 * s2 + s3) / static_cast<double>(m);
      squares += d * d;
    }
    total += squares / (6.0 * static_cast<double>(m));
  }
  return static_cast<double>(total / windows);
}

// White, random-walk and integrated random-walk phase (white PM, white FM, random-walk FM),
// with an offset and a frequency offset, which no total deviation sees.
std::vector<std::vector<double>> random_phases(std::size_t n) {
  std::mt19937_64 rng(48);
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

TEST(TotalDeviations, EqualTheirWindowByWindowDefinitionOnRandomSeries) {
  // Factors on both sides of the direct reading (m <= 8) and up to the last window; tau0 = 0.5.
  const double tau0 = 0.5;
  const std::vector<std::int64_t> mtot = {1, 2, 3, 5, 8, 9, 10, 16, 33, 64, 100, 257, 333, 400};
  const std::vector<std::int64_t> htot = {2, 3, 8, 9, 10, 33, 100, 257, 399};
  for (const std::vector<double>& x : random_phases(1201)) {
    const DeviationCurve mc = deviation(DeviationKind::kMtotdev, x, tau0, mtot);
    for (std::size_t k = 0; k < mtot.size(); ++k) {
      const double tau = static_cast<double>(mtot[k]) * tau0;
      EXPECT_NEAR(mc.value[k] / std::sqrt(literal_total(x, mtot[k]) / (2.0 * tau * tau)), 1.0, 1e-10)
          << "m " << mtot[k];
    }
    std::vector<double> y;
    for (std::size_t i = 0; i + 1 < x.size(); ++i) y.push_back((x[i + 1] - x[i]) / tau0);
    const DeviationCurve hc = deviation(DeviationKind::kHtotdev, x, tau0, htot);
    for (std::size_t k = 0; k < htot.size(); ++k)
      EXPECT_NEAR(hc.value[k] / std::sqrt(literal_total(y, htot[k]) / 6.0), 1.0, 1e-10) << "m " << htot[k];
  }
}

TEST(TotalDeviations, TimeTotalIsTauTimesModifiedTotalOverRootThreeAndHadamardTotalIsOhdevAtOne) {
  const std::vector<double> x = phase_dat();
  const std::vector<std::int64_t> m = {1, 7, 50, 333};
  const DeviationCurve mod = deviation(DeviationKind::kMtotdev, x, 0.01, m);
  const DeviationCurve time = deviation(DeviationKind::kTtotdev, x, 0.01, m);
  for (std::size_t k = 0; k < m.size(); ++k)
    EXPECT_NEAR(time.value[k] / (mod.value[k] * mod.tau[k] / std::sqrt(3.0)), 1.0, 1e-14);
  const std::vector<std::int64_t> one = {1};
  EXPECT_EQ(deviation(DeviationKind::kHtotdev, x, 0.01, one).value,
            deviation(DeviationKind::kOhdev, x, 0.01, one).value);
  EXPECT_TRUE(in_time_units(DeviationKind::kTtotdev));
  EXPECT_FALSE(in_time_units(DeviationKind::kMtotdev));
  EXPECT_FALSE(in_time_units(DeviationKind::kHtotdev));
  EXPECT_EQ(max_factor(DeviationKind::kMtotdev, 1001), 333);
  EXPECT_EQ(max_factor(DeviationKind::kHtotdev, 1001), 333);
  EXPECT_EQ(terms(DeviationKind::kHtotdev, 1001, 333), 2);
}

}  // namespace
}  // namespace gmwm::stability
