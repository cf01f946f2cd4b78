// Selection accuracy (issues 4 and 13): for each true model, 100 series of length 2^17
// are simulated and every sub-model of 3*AR1+WN+RW+QN+DR (63) is fitted and ranked, once
// by the WVIC (objective + analytic optimism) and once by the consistent BIC-type penalty
// (objective + p log N), both with the selection's default Omega. The ranking's rows are
// effective models (effective_model.h: an AR1 at phi -> 1 reads as the RW it stands for,
// collapsed terms dropped), so "effective truth first" counts equivalent forms as the
// truth; "as fitted" asks whether the best-scoring candidate itself was the truth's
// structure. Four truths with every component detectable (non-centrality >= 25 under the
// exact WV covariance, with the other components known and with them re-estimated) and
// one with a borderline component (nc 2-8), whose oracle power is printed. Also the representation violations over every selection (bar 0). Goal: the
// effective truth first in >= 80% of the series of each fully detectable truth, with WVIC
// and with BIC. Seeds fixed below. Exit 0 when the goal and the bar hold.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "bench_common.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/engine/wv_covariance.h"
#include "gmwm/selection/select.h"

using namespace gmwm;

namespace {

constexpr std::int64_t kN = 1 << 17;
constexpr int kReplicates = 100;
constexpr double kGoal = 0.80;
constexpr double kDetectableNc = 25.0;
constexpr const char* kMaximal = "3*AR1+WN+RW+QN+DR";

// Per component of the truth: the non-centrality nc = d' V0^-1 d of its WV d (at the true
// values) under the exact covariance V0 of nuhat at the truth, J = log2 N levels. It
// bounds what any WV-based selection can see: dropping the component and refitting the
// others shifts the expected WV by at most d, so no test has more power than the oracle
// test with power Phi(sqrt(nc) - z_0.95).
std::vector<double> noncentrality(const Model& truth) {
  const int J = static_cast<int>(std::log2(static_cast<double>(kN)));
  std::vector<double> tau;
  for (int j = 1; j <= J; ++j) tau.push_back(std::ldexp(1.0, j));
  const Eigen::VectorXd theta = truth.given_values();
  const Eigen::MatrixXd v0 = model_wv_covariance(truth, theta, kN, J);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(v0);
  std::vector<double> out;
  for (int c = 0; c < truth.num_components(); ++c) {
    const Process& p = *truth.components()[static_cast<std::size_t>(c)].process;
    std::vector<double> f(tau.size());
    p.wv({theta.data() + truth.offset(c), static_cast<std::size_t>(p.size())}, tau, f);
    const Eigen::VectorXd d = Eigen::Map<const Eigen::VectorXd>(f.data(), J);
    out.push_back(d.dot(ldlt.solve(d)));
  }
  return out;
}

// The same with the other components re-estimated: the minimum over the model without
// component c of (nu0 - nu(theta))' V0^-1 (nu0 - nu(theta)), nu0 the truth's exact WV. It
// is what a test that knows the forms but not the values can see (a component another one
// can mimic, like a WN beside an AR1 and a QN, is much less visible than nc says).
std::vector<double> refit_noncentrality(const Model& truth) {
  const int J = static_cast<int>(std::log2(static_cast<double>(kN)));
  WaveletVariance w;
  for (int j = 1; j <= J; ++j) {
    const double tau = std::ldexp(1.0, j);
    w.tau.push_back(tau);
    w.coefficients.push_back(kN - static_cast<std::int64_t>(tau) + 1);
    w.eta.push_back(std::max(static_cast<double>(w.coefficients.back()) / tau, 1.0));
    w.notes.emplace_back();
  }
  w.n = kN;
  const Eigen::VectorXd theta = truth.given_values();
  const Eigen::VectorXd nu0 = truth.wv(theta, w.tau);
  w.wv.assign(nu0.data(), nu0.data() + J);
  w.ci_low = w.ci_high = w.variance = w.wv;
  const Eigen::MatrixXd v0 = model_wv_covariance(truth, theta, kN, J);
  const Eigen::MatrixXd omega = v0.ldlt().solve(Eigen::MatrixXd::Identity(J, J));
  std::vector<double> out;
  for (int c = 0; c < truth.num_components(); ++c) {
    std::vector<Component> kept;
    Eigen::VectorXd start(truth.num_parameters() - truth.components()[static_cast<std::size_t>(c)].process->size());
    int pos = 0;
    for (int k = 0; k < truth.num_components(); ++k) {
      if (k == c) continue;
      kept.push_back(truth.components()[static_cast<std::size_t>(k)]);
      const int size = truth.components()[static_cast<std::size_t>(k)].process->size();
      start.segment(pos, size) = theta.segment(truth.offset(k), size);
      pos += size;
    }
    FitOptions fo;
    fo.omega_matrix = omega;
    fo.inference = false;
    fo.starts = {start};
    out.push_back(fit_gmwm(w, Model(kept), fo).objective);
  }
  return out;
}

// The oracle's power for one component: the chi-square test (1 df, level 5%) of its
// absence with every other parameter known, non-centrality nc.
double oracle_power(double nc) {
  const double q = boost::math::quantile(boost::math::chi_squared(1.0), 0.95);
  return boost::math::cdf(boost::math::complement(boost::math::non_central_chi_squared(1.0, nc), q));
}

using Counts = std::map<std::string, int>;

selection::OmegaSource g_omega = selection::OmegaSource::kModel;

Counts components(const std::string& spec) {
  Counts c;
  const Model m = parse_model(spec);
  for (const auto& comp : m.components()) ++c[comp.process->name()];
  return c;
}

bool contains(const Counts& model, const Counts& truth) {
  for (const auto& [k, v] : truth) {
    const auto it = model.find(k);
    if (it == model.end() || it->second < v) return false;
  }
  return true;
}

// "+QN", "-AR1", ...: what `picked` adds to or misses from `truth`.
std::string difference(const Counts& picked, const Counts& truth) {
  std::string out;
  std::map<std::string, int> all = picked;
  for (const auto& [k, v] : truth) all[k] = std::max(all[k], 0);
  for (const auto& [k, v] : all) {
    const int have = picked.count(k) ? picked.at(k) : 0, need = truth.count(k) ? truth.at(k) : 0;
    for (int i = need; i < have; ++i) out += " +" + k;
    for (int i = have; i < need; ++i) out += " -" + k;
  }
  return out.empty() ? " (none)" : out;
}

struct Tally {
  int first = 0, as_fitted = 0, contained = 0;
  std::map<std::string, int> wrong;  // difference -> count
};

std::string top_wrong(const Tally& t) {
  std::vector<std::pair<int, std::string>> v;
  for (const auto& [k, n] : t.wrong) v.emplace_back(-n, k);
  std::sort(v.begin(), v.end());
  std::string out;
  for (std::size_t i = 0; i < v.size() && i < 4; ++i)
    out += std::string(i ? ", " : "") + (v[i].second.c_str() + 1) + " (" + std::to_string(-v[i].first) + ")";
  return out.empty() ? "-" : out;
}

struct Detectability {
  std::string text;        // per component: nc and oracle power
  bool all_detectable = true;
};

Detectability detectability(const Model& truth) {
  Detectability d;
  const auto nc = noncentrality(truth);
  const auto refit = refit_noncentrality(truth);
  for (int c = 0; c < truth.num_components(); ++c) {
    const auto& comp = truth.components()[static_cast<std::size_t>(c)];
    const double v = nc[static_cast<std::size_t>(c)], r = refit[static_cast<std::size_t>(c)];
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s%s nc %.3g (oracle power %.0f%%), with the others re-estimated %.3g (power %.0f%%)",
                  c ? "; " : "", comp.process->name().c_str(), v, 100 * oracle_power(v), r, 100 * oracle_power(r));
    d.text += buf;
    d.all_detectable = d.all_detectable && v >= kDetectableNc && r >= kDetectableNc;
  }
  return d;
}

struct Pick {
  std::string effective, fitted;
  int violations = 0;
};

int g_violations = 0, g_selections = 0;

bool study(const char* truth_spec, std::uint64_t seed, std::vector<std::string>& notes) {
  const Model truth = parse_model(truth_spec);
  const std::string want_name = truth.to_string();
  const Counts want = components(want_name);
  const Detectability det = detectability(truth);
  const Model maximal = parse_model(kMaximal);
  std::vector<Pick> pick_wvic(kReplicates), pick_bic(kReplicates);
  tbb::parallel_for(0, kReplicates, [&](int r) {
    const auto x = simulate(truth, truth.given_values(), kN, seed, static_cast<std::uint64_t>(r));
    const std::vector<WaveletVariance> wv = {classical_wv(x.data(), kN)};
    selection::SelectOptions o;
    o.omega = g_omega;
    auto pick = [&](const selection::Selection& sel) {
      return Pick{sel.ranking.front().model, sel.ranking.front().members.front(), sel.representation_violations};
    };
    pick_wvic[static_cast<std::size_t>(r)] = pick(selection::select_models(wv, maximal, o).front());
    o.penalty = selection::Penalty::kBic;
    pick_bic[static_cast<std::size_t>(r)] = pick(selection::select_models(wv, maximal, o).front());
  });
  auto tally = [&](const std::vector<Pick>& picks) {
    Tally t;
    for (const auto& p : picks) {
      const Counts c = components(p.effective);
      if (p.effective == want_name) ++t.first;
      else ++t.wrong[difference(c, want)];
      if (p.fitted == want_name) ++t.as_fitted;
      if (contains(c, want)) ++t.contained;
      g_violations += p.violations;
      ++g_selections;
    }
    return t;
  };
  const Tally w = tally(pick_wvic), b = tally(pick_bic);
  auto pct = [](int n) { return 100.0 * n / kReplicates; };
  std::printf("| %s | WVIC | %.0f%% | %.0f%% | %.0f%% | %s |\n", truth_spec, pct(w.first), pct(w.as_fitted),
              pct(w.contained), top_wrong(w).c_str());
  std::printf("| | BIC | %.0f%% | %.0f%% | %.0f%% | %s |\n", pct(b.first), pct(b.as_fitted), pct(b.contained),
              top_wrong(b).c_str());
  notes.push_back(std::string(truth_spec) + ": " + det.text + (det.all_detectable ? "." : " (a borderline component)."));
  std::fflush(stdout);
  return !det.all_detectable || (w.first >= kGoal * kReplicates && b.first >= kGoal * kReplicates);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  // Optional arguments, for diagnostics: the Omega (data | model | full) and one truth (1-3).
  const std::string omega = argc > 1 ? argv[1] : "model";
  const int only = argc > 2 ? std::atoi(argv[2]) : 0;
  g_omega = omega == "data" ? selection::OmegaSource::kData
            : omega == "full" ? selection::OmegaSource::kModelFull : selection::OmegaSource::kModel;
  bench::Stopwatch clock;
  std::printf("%d series of N = 2^17 per true model, every sub-model of %s (63), Omega %s; "
              "WVIC = objective + analytic optimism, BIC = objective + p log N.\n\n", kReplicates, kMaximal,
              selection::to_string(g_omega));
  std::printf("| true model | criterion | effective truth first | truth first as fitted | first contains the truth | "
              "wrong picks: difference from the truth (count) |\n|---|---|---|---|---|---|\n");
  bool ok = true;
  std::vector<std::string> notes;
  const char* truths[] = {"WN(sigma2=1)+QN(Q2=1)+RW(gamma2=3e-6)",
                          "AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=2)+RW(gamma2=1e-4)",
                          "AR1(phi=0.95,sigma2=0.05)+AR1(phi=0.998,sigma2=3e-4)+WN(sigma2=1)",
                          "AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)+QN(Q2=0.3)+DR(omega=1e-4)",
                          "WN(sigma2=1)+RW(gamma2=1e-7)"};
  if (only < 0) {  // detectability only: of the truths below, or of the models given after "-1"
    std::vector<std::string> notes;
    std::vector<std::string> specs(std::begin(truths), std::end(truths));
    if (argc > 3) specs.assign(argv + 3, argv + argc);
    for (const auto& t : specs) notes.push_back(t + ": " + detectability(parse_model(t)).text);
    for (const auto& n : notes) std::printf("- %s\n", n.c_str());
    return 0;
  }
  for (int t = 0; t < 5; ++t)
    if (!only || only == t + 1) ok &= study(truths[t], 5101 + static_cast<std::uint64_t>(t), notes);
  std::printf("\nDetectability of each true component at N = 2^17: non-centrality nc = d' V0^-1 d of its WV d under "
              "the exact Cov(nuhat) at the truth, and the power of the oracle test of its absence (all other "
              "parameters known; chi-square, 1 df, 5%%): an upper bound for any WV-based selection; and the same "
              "with the other components re-estimated (the minimum over the model without it of the exact WV's "
              "V0^-1 distance: what a test that knows the forms can see). Fully detectable = both >= %.0f for every "
              "component.\n\n", kDetectableNc);
  for (const auto& n : notes) std::printf("- %s\n", n.c_str());
  std::printf("\nRepresentation violations over the %d selections (63 candidates each): %d (bar 0).\n", g_selections,
              g_violations);
  ok = ok && g_violations == 0;
  std::printf("\nGoal: the effective truth first in at least %.0f%% of the series of each fully detectable truth, "
              "with WVIC and with BIC, and no representation violation: %s (%.0f s).\n",
              100 * kGoal, ok ? "pass" : "FAIL", clock.seconds());
  return ok ? 0 : 1;
}
