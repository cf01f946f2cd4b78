// The power-law read-offs' rules shared by the data's and a model's curve
// (noise_figures_internal.h): which slope region each figure is read on, and the
// separation of the lines where several are read (docs/noise-figures.md, "Reading a curve").
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "noise_figures_internal.h"

namespace gmwm::figures {

namespace {

// Two slope stretches are as long as each other within this (octaves): rounding.
constexpr double kSameOctaves = 1e-9;

// N: the white floor, the longest straight -1/2 stretch (the finer on a tie). The one
// nearest the IEEE tau read a short stretch after a tone's bump on the ADIS accelerometers'
// z axes, 19-29% above the floor (issue 43, item 3). Over the record only: a model's curve
// is searched far beyond it, where a slow AR1's white tail would be the longest stretch of
// all.
const Region* longest_region(const Curve& c, const std::vector<Region>& regions, double ieee_tau) {
  auto octaves = [&](const Region& r) {
    std::size_t last = r.first;
    for (std::size_t i = r.first; i <= r.last && c.bounds_from(i); ++i) last = i;
    return std::log2(c.tau[last] / c.tau[r.first]);
  };
  const Region* best = nullptr;
  for (const auto& r : regions)
    if (r.count >= kMinRegionPoints && c.bounds_from(r.first) && (!best || octaves(r) > octaves(*best) + kSameOctaves))
      best = &r;
  if (!best)  // a model whose white noise shows beyond the record only: the nearest stretch
    for (const auto& r : regions)
      if (r.count >= kMinRegionPoints &&
          (!best || std::log(c.tau[r.first] / ieee_tau) < std::log(c.tau[best->first] / ieee_tau)))
        best = &r;
  return best;
}

// K: the region holding the IEEE tau, else the one nearest to it.
const Region* nearest_region(const Curve& c, const std::vector<Region>& regions, double ieee_tau) {
  auto log_distance = [&](std::size_t i) { return std::abs(std::log(c.tau[i] / ieee_tau)); };
  auto distance = [&](const Region& r) {
    if (c.tau[r.first] <= ieee_tau && ieee_tau <= c.tau[r.last]) return 0.0;
    return std::min(log_distance(r.first), log_distance(r.last));
  };
  const Region* best = nullptr;
  for (const auto& r : regions)
    if (r.count >= kMinRegionPoints && (!best || distance(r) < distance(*best))) best = &r;
  return best;
}

}  // namespace

// Q and R: quantization is the steepest falling term (-1), so it shows first, at the curve's
// shortest taus; a ramp the steepest rising one (+1), so it shows last. A -1 stretch after a
// bump is a tone's fall past its period (a sinusoid's Allan deviation falls as 1 / tau), and a
// +1 stretch before one is a tone's or a correlated term's rise: neither is read as Q or R.
const Region* pick_region(const Curve& c, const std::vector<Region>& regions, const SlopeFigure& s) {
  switch (s.rule) {
    case RegionRule::kLongest:
      return longest_region(c, regions, s.tau);
    case RegionRule::kNearest:
      return nearest_region(c, regions, s.tau);
    case RegionRule::kFirst:
    case RegionRule::kLast:
      break;
  }
  std::size_t first = c.tau.size(), last = c.tau.size();
  for (std::size_t i = 0; i < c.tau.size(); ++i) {
    if (!c.usable[i] || !(c.sigma[i] > 0.0)) continue;
    if (first == c.tau.size()) first = i;
    last = i;
  }
  for (const auto& r : regions)
    if (r.count >= kMinRegionPoints && (s.rule == RegionRule::kFirst ? r.first == first : r.last == last)) return &r;
  return nullptr;
}

namespace {

struct Line {
  Readoff* r;
  const SlopeFigure* s;
  const char* name;
};

// Solves AVAR(tau_i) = sum_j F_j^2 / scale_j(tau_i)^2 at the lines' read points for the F_j^2
// and rescales each read-off (and its interval) to its own line's share; false (nothing
// changed) unless every F_j^2 comes out positive. The rows are scaled to 1 and the columns to
// their largest entry (the taus span decades and the powers reach tau^+-2).
bool separate(const std::vector<Line>& lines) {
  const auto n = static_cast<Eigen::Index>(lines.size());
  if (n < 2) return false;
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Readoff& ri = *lines[static_cast<std::size_t>(i)].r;
    const double avar = std::pow(ri.value / lines[static_cast<std::size_t>(i)].s->scale(ri.tau), 2);
    for (Eigen::Index j = 0; j < n; ++j)
      A(i, j) = 1.0 / std::pow(lines[static_cast<std::size_t>(j)].s->scale(ri.tau), 2) / avar;
  }
  const Eigen::RowVectorXd norm = A.cwiseAbs().colwise().maxCoeff();
  for (Eigen::Index j = 0; j < n; ++j) A.col(j) /= norm(j);
  const Eigen::VectorXd x = A.fullPivLu().solve(Eigen::VectorXd::Ones(n)).cwiseQuotient(norm.transpose());
  if (!x.allFinite() || !(x.minCoeff() > 0.0)) return false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    Readoff& r = *lines[i].r;
    const double ratio = std::sqrt(x(static_cast<Eigen::Index>(i))) / r.value;
    r.value *= ratio, r.low *= ratio, r.high *= ratio;
    std::string others;
    for (std::size_t j = 0; j < lines.size(); ++j)
      if (j != i) others += std::string(others.empty() ? "" : " and ") + lines[j].name + "'s";
    r.how += "; the " + others + (lines.size() > 2 ? " shares" : " share") + " at " + fmt(r.tau) + " s removed";
  }
  return true;
}

}  // namespace

// Each read point carries the other lines: AVAR = 3 Q^2 / tau^2 + N^2 / tau + K^2 tau / 3 +
// R^2 tau^2 / 2 (IEEE 952 C.1; the terms add). Solving the equations at the read points
// removes them (a +1/2 region starting where the white noise still adds a quarter of the
// variance would otherwise read K 12% high; a -1 region ends where the white noise adds up to
// a fifth, Q 10% high). The lines must be read in their order along tau (Q, N, K, R: each
// steeper line dominates further from the middle); else, or when a solution is not positive,
// the N and K pair alone is separated as before Q and R were read.
void separate_power_laws(NoiseFigures& f) {
  std::vector<Line> all;
  for (const Line& l :
       {Line{&f.quantization, &kQuantizationSlope, "quantization noise"}, Line{&f.white, &kWhiteSlope, "white noise"},
        Line{&f.walk, &kWalkSlope, "random walk"}, Line{&f.ramp, &kRampSlope, "rate ramp"}})
    if (shows(*l.r) && l.r->tau > 0.0) all.push_back(l);
  bool ordered = true;
  for (std::size_t i = 1; i < all.size(); ++i) ordered = ordered && all[i].r->tau > all[i - 1].r->tau;
  if (ordered && separate(all)) return;
  if (all.size() > 2 && shows(f.white) && shows(f.walk) && f.walk.tau > f.white.tau)
    separate({Line{&f.white, &kWhiteSlope, "white noise"}, Line{&f.walk, &kWalkSlope, "random walk"}});
}

}  // namespace gmwm::figures
