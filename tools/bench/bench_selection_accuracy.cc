// Selection accuracy (issues 4 and 13): for each true model, 100 series of length 2^17
// are simulated and every sub-model of 3*AR1+WN+RW+QN+DR (63) is fitted and ranked, once
// by the WVIC (objective + analytic optimism) and once by the consistent BIC-type penalty
// (objective + p log N), both with the selection's default Omega. The ranking's rows are
// effective models (effective_model.h: an AR1 at phi -> 1 reads as the RW it stands for,
// collapsed terms dropped), so "effective truth first" counts equivalent forms as the
// truth; "as fitted" asks whether the best-scoring candidate itself was the truth's
// structure. Four truths with every component detectable (non-centrality >= 25 under the
// exact WV covariance, with the other components known and with them re-estimated) and
// one with a borderline component (nc 2-8), whose oracle power is printed; and one with a
// slow AR1 the data only just resolve (issue 27), where "effective truth first" is set
// against the Monte-Carlo oracle that knows the forms: the same criterion choosing between
// the truth and the truth without its slow AR1 only (select_among on the two), on the same
// series. Also: the representation violations over every selection (bar 0), and every row
// of every WVIC selection refitted alone (its model, the selection's Omega, default
// starts): no refit may end below the row's objective (relative 1e-6), since a row is its
// own model's fit. Goal (issue 27): the effective truth first in >= 85% of the series of
// each fully detectable truth, and within 10 points of the oracle for the slow-AR1 truth,
// with WVIC and with BIC. Seeds fixed below. Exit 0 when the goals and the bars hold.
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
#include "bench_detectability.h"
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
constexpr double kGoal = 0.85;
constexpr double kOracleGap = 0.10;  // points of the oracle, slow-AR1 truth
constexpr double kDetectableNc = 25.0;
constexpr const char* kMaximal = "3*AR1+WN+RW+QN+DR";

std::vector<double> noncentrality(const Model& truth) { return bench::noncentrality(truth, kN); }
std::vector<double> refit_noncentrality(const Model& truth) { return bench::refit_noncentrality(truth, kN); }
using bench::oracle_power;

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
  int first = 0, as_fitted = 0, contained = 0, oracle = 0;
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
  std::string text;  // per component: nc and oracle power
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
    std::snprintf(buf, sizeof buf,
                  "%s%s nc %.3g (oracle power %.0f%%), with the others re-estimated %.3g (power %.0f%%)", c ? "; " : "",
                  comp.process->name().c_str(), v, 100 * oracle_power(v), r, 100 * oracle_power(r));
    d.text += buf;
    d.all_detectable = d.all_detectable && v >= kDetectableNc && r >= kDetectableNc;
  }
  return d;
}

struct Pick {
  std::string effective, fitted;
  int violations = 0;
  bool oracle_truth = false;  // the criterion prefers the truth over the truth without its slow AR1
};

int g_violations = 0, g_selections = 0;
int g_rows = 0, g_rows_below = 0;  // rows refitted alone; refits ending below the row
double g_worst_row = 0.0;          // largest relative amount a refit ended below its row

// Every row of `sel` refitted alone from the default starts under the selection's Omega.
void check_rows(const WaveletVariance& wv, const selection::Selection& sel) {
  for (const auto& row : sel.ranking) {
    FitOptions fo;
    fo.omega_matrix = sel.omega;
    fo.inference = false;
    const FitResult alone = fit_gmwm(wv, parse_model(row.model), fo);
    const double rel = (row.objective - alone.objective) / std::max(std::abs(row.objective), 1e-300);
    ++g_rows;
    if (rel > 1e-6) ++g_rows_below;
    g_worst_row = std::max(g_worst_row, rel);
  }
}

// The truth without its slowest AR1 (the oracle's alternative), or "" when it has no two AR1s.
std::string without_slow_ar1(const Model& truth) {
  int slow = -1, ar1s = 0;
  for (int c = 0; c < truth.num_components(); ++c)
    if (truth.components()[static_cast<std::size_t>(c)].process->name() == "AR1") {
      ++ar1s;
      if (slow < 0 || truth.given_values()(truth.offset(c)) > truth.given_values()(truth.offset(slow))) slow = c;
    }
  if (ar1s < 2) return "";
  std::vector<Component> kept;
  for (int c = 0; c < truth.num_components(); ++c)
    if (c != slow) kept.push_back(truth.components()[static_cast<std::size_t>(c)]);
  return Model(kept).to_string();
}

bool study(const char* truth_spec, std::uint64_t seed, bool oracle, std::vector<std::string>& notes) {
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
    auto oracle_pick = [&](Pick& p) {
      if (!oracle) return;
      const std::vector<Model> two = {parse_model(want_name), parse_model(without_slow_ar1(truth))};
      p.oracle_truth = selection::select_among(wv, two, o).front().ranking.front().model == want_name;
    };
    const selection::Selection sw = selection::select_models(wv, maximal, o).front();
    check_rows(wv.front(), sw);
    pick_wvic[static_cast<std::size_t>(r)] = pick(sw);
    oracle_pick(pick_wvic[static_cast<std::size_t>(r)]);
    o.penalty = selection::Penalty::kBic;
    pick_bic[static_cast<std::size_t>(r)] = pick(selection::select_models(wv, maximal, o).front());
    oracle_pick(pick_bic[static_cast<std::size_t>(r)]);
  });
  auto tally = [&](const std::vector<Pick>& picks) {
    Tally t;
    for (const auto& p : picks) {
      const Counts c = components(p.effective);
      if (p.effective == want_name)
        ++t.first;
      else
        ++t.wrong[difference(c, want)];
      if (p.fitted == want_name) ++t.as_fitted;
      if (contains(c, want)) ++t.contained;
      if (p.oracle_truth) ++t.oracle;
      g_violations += p.violations;
      ++g_selections;
    }
    return t;
  };
  const Tally w = tally(pick_wvic), b = tally(pick_bic);
  auto pct = [](int n) { return 100.0 * n / kReplicates; };
  auto oracle_text = [&](const Tally& t) { return oracle ? std::to_string(t.oracle) + "%" : std::string("-"); };
  std::printf("| %s | WVIC | %.0f%% | %s | %.0f%% | %.0f%% | %s |\n", truth_spec, pct(w.first), oracle_text(w).c_str(),
              pct(w.as_fitted), pct(w.contained), top_wrong(w).c_str());
  std::printf("| | BIC | %.0f%% | %s | %.0f%% | %.0f%% | %s |\n", pct(b.first), oracle_text(b).c_str(),
              pct(b.as_fitted), pct(b.contained), top_wrong(b).c_str());
  notes.push_back(std::string(truth_spec) + ": " + det.text +
                  (det.all_detectable ? "." : " (a borderline component)."));
  std::fflush(stdout);
  if (oracle)
    return std::abs(w.first - w.oracle) <= kOracleGap * kReplicates &&
           std::abs(b.first - b.oracle) <= kOracleGap * kReplicates;
  return !det.all_detectable || (w.first >= kGoal * kReplicates && b.first >= kGoal * kReplicates);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::err);
  // Optional arguments, for diagnostics: the Omega (data | model | full) and one truth (1-3).
  const std::string omega = argc > 1 ? argv[1] : "model";
  const int only = argc > 2 ? std::atoi(argv[2]) : 0;
  g_omega = omega == "data"   ? selection::OmegaSource::kData
            : omega == "full" ? selection::OmegaSource::kModelFull
                              : selection::OmegaSource::kModel;
  bench::Stopwatch clock;
  std::printf(
      "%d series of N = 2^17 per true model, every sub-model of %s (63), Omega %s; "
      "WVIC = objective + analytic optimism, BIC = objective + p log N.\n\n",
      kReplicates, kMaximal, selection::to_string(g_omega));
  std::printf(
      "| true model | criterion | effective truth first | oracle (truth vs truth without its slow AR1) | "
      "truth first as fitted | first contains the truth | "
      "wrong picks: difference from the truth (count) |\n|---|---|---|---|---|---|---|\n");
  bool ok = true;
  std::vector<std::string> notes;
  const char* truths[] = {"WN(sigma2=1)+QN(Q2=1)+RW(gamma2=3e-6)",
                          "AR1(phi=0.99,sigma2=1e-3)+WN(sigma2=2)+RW(gamma2=1e-4)",
                          "AR1(phi=0.95,sigma2=0.05)+AR1(phi=0.998,sigma2=3e-4)+WN(sigma2=1)",
                          "AR1(phi=0.9,sigma2=0.1)+WN(sigma2=1)+QN(Q2=0.3)+DR(omega=1e-4)",
                          "WN(sigma2=1)+RW(gamma2=1e-7)",
                          "AR1(phi=0.9,sigma2=0.1)+AR1(phi=0.999,sigma2=1e-5)+WN(sigma2=1)"};
  constexpr int kTruths = 6, kSlowAr1Truth = 5;  // the last: the oracle's
  if (only < 0) {  // detectability only: of the truths below, or of the models given after "-1"
    std::vector<std::string> notes;
    std::vector<std::string> specs(std::begin(truths), std::end(truths));
    if (argc > 3) specs.assign(argv + 3, argv + argc);
    for (const auto& t : specs) notes.push_back(t + ": " + detectability(parse_model(t)).text);
    for (const auto& n : notes) std::printf("- %s\n", n.c_str());
    return 0;
  }
  for (int t = 0; t < kTruths; ++t)
    if (!only || only == t + 1) ok &= study(truths[t], 5101 + static_cast<std::uint64_t>(t), t == kSlowAr1Truth, notes);
  std::printf(
      "\nDetectability of each true component at N = 2^17: non-centrality nc = d' V0^-1 d of its WV d under "
      "the exact Cov(nuhat) at the truth, and the power of the oracle test of its absence (all other "
      "parameters known; chi-square, 1 df, 5%%): an upper bound for any WV-based selection; and the same "
      "with the other components re-estimated (the minimum over the model without it of the exact WV's "
      "V0^-1 distance: what a test that knows the forms can see). Fully detectable = both >= %.0f for every "
      "component.\n\n",
      kDetectableNc);
  for (const auto& n : notes) std::printf("- %s\n", n.c_str());
  std::printf("\nRepresentation violations over the %d selections (63 candidates each): %d (bar 0).\n", g_selections,
              g_violations);
  std::printf(
      "\nRows refitted alone (every row of every WVIC selection, default starts, the selection's Omega): %d; "
      "refits ending below their row by more than 1e-6 relative: %d (bar 0; largest %.2g).\n",
      g_rows, g_rows_below, g_worst_row);
  ok = ok && g_violations == 0 && g_rows_below == 0;
  std::printf(
      "\nGoal: the effective truth first in at least %.0f%% of the series of each fully detectable truth, "
      "within %.0f points of the oracle for the slow-AR1 truth, with WVIC and with BIC, no representation "
      "violation and no row below its refit: %s (%.0f s).\n",
      100 * kGoal, 100 * kOracleGap, ok ? "pass" : "FAIL", clock.seconds());
  return ok ? 0 : 1;
}
