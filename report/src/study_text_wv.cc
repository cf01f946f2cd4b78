// The terminal and CSV tables of `gmwm wv` (and --adev) (study_text.h).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <sstream>

#include "gmwm/io/signal_writer.h"
#include "gmwm/report/study_text.h"

namespace gmwm::report {
namespace {

// Shortest text that reads back to the same double ("nan" when not finite).
std::ostream& num(std::ostream& o, double x) {
  if (!std::isfinite(x)) return o << "nan";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return o.write(buf, r.ptr - buf);
}

// The record's tenths a screen's histogram counts in.
constexpr int kScreeningBins = 10;

}  // namespace

std::string screening_summary(const WaveletVariance& wv, std::int64_t n, double freq, bool freq_known) {
  if (wv.replaced.empty() || n <= 0) return {};
  std::int64_t samples = 0, longest = 0, longest_at = 0;
  std::array<std::int64_t, kScreeningBins> bins{};
  for (const auto& [a, b] : wv.replaced) {
    samples += b - a + 1;
    if (b - a + 1 > longest) longest = b - a + 1, longest_at = a;
    // In double: a grid position times the bins may pass 2^63 on a record with long gaps.
    const auto bin = static_cast<std::int64_t>(
        std::min(kScreeningBins - 1.0, std::floor(static_cast<double>(a) * kScreeningBins / static_cast<double>(n))));
    ++bins[static_cast<std::size_t>(bin)];
  }
  const auto when = [&](std::int64_t i) {
    return freq_known ? fmt(static_cast<double>(i) / freq, 6) + " s" : "sample " + std::to_string(i);
  };
  std::ostringstream os;
  os << "spike screen: " << samples << " sample" << (samples == 1 ? "" : "s") << " in " << wv.replaced.size()
     << " range" << (wv.replaced.size() == 1 ? "" : "s") << " replaced by interpolation ("
     << fmt(100.0 * static_cast<double>(samples) / static_cast<double>(n), 3) << "% of the record), from "
     << when(wv.replaced.front().first) << " to " << when(wv.replaced.back().second) << "; the longest " << longest
     << " sample" << (longest == 1 ? "" : "s") << " at " << when(longest_at) << "\n";
  os << "  ranges in each tenth of the record:";
  for (const std::int64_t b : bins) os << ' ' << b;
  os << " (the JSON's screening.replaced_ranges lists them all)\n";
  return os.str();
}

std::string wv_text(const io::SignalSet& set, const pipeline::WvStudy& study) {
  std::ostringstream os;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const auto& w = study.columns[k].wv;
    const std::optional<pipeline::RobustWvView>& rv = study.columns[k].robust;
    const auto& s = set.signals[k];
    if (k) os << '\n';
    const bool gaps = !set.missing.empty();
    os << s.name << ": N = " << s.values.size();
    if (gaps)
      os << " observed of " << w.n << " (" << set.missing_samples() << " missing in " << set.missing.size()
         << (set.missing.size() == 1 ? " gap" : " gaps") << ")";
    os << ", " << fmt(set.freq) << " Hz, ";
    if (rv)
      os << w.estimator << " WV (efficiency " << fmt(w.efficiency.value_or(1.0)) << ")";
    else
      os << "classical WV";
    os << ", " << fmt(100.0 * (1.0 - w.alpha)) << "% CI" << (s.unit.empty() ? "" : ", WV in (" + s.unit + ")^2")
       << '\n';
    std::vector<std::string> head = {"level", "tau", "tau [s]", "WV", "CI low", "CI high", "M_j"};
    if (gaps) head.insert(head.end(), {"partial", "lost"});  // windows read missing some; not read
    if (rv) head.insert(head.end(), {"classical", "ratio", "flag"});
    TextTable t(head);
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      std::vector<std::string> row = {std::to_string(j + 1),
                                      fmt(w.tau[l], 10),
                                      fmt(w.tau[l] / set.freq),
                                      std::isfinite(w.wv[l]) ? fmt(w.wv[l]) : "no root",
                                      fmt(w.ci_low[l]),
                                      fmt(w.ci_high[l]),
                                      std::to_string(w.coefficients[l])};
      if (gaps)
        row.insert(row.end(), {l < w.partial.size() ? std::to_string(w.partial[l]) : "0",
                               std::to_string(w.n - static_cast<std::int64_t>(w.tau[l]) + 1 - w.coefficients[l])});
      if (rv) {
        const auto& d = rv->diagnostic[l];
        row.insert(row.end(), {fmt(d.classical_wv), fmt(d.robust_to_classical, 4),
                               d.contaminated ? "contaminated" : (d.ci_disjoint ? "CIs disjoint" : "")});
      }
      t.add(row);
    }
    os << t.str();
    if (gaps) {
      os << "M_j: the windows of tau samples read; partial: those of them missing some samples (each half at most "
            "a tenth, averaged over its observed ones; read where complete windows are scarce); lost: the rest\n";
      const std::int64_t longest = io::longest_stretch(set);
      int deepest = 0;
      while (deepest < 62 && (std::int64_t{2} << deepest) <= w.n) ++deepest;
      if (study.levels_asked > 0) deepest = std::min(deepest, study.levels_asked);
      // A level is dropped only when it has no window free of gaps and none missing at most a
      // tenth of each half; the fit reads consecutive levels, so the deeper ones go with it.
      if (w.levels() < deepest && !w.tau.empty())
        os << "levels " << w.levels() + 1 << "-" << deepest << ": not read, level " << w.levels() + 1
           << " has no window of " << fmt(2.0 * w.tau.back(), 10)
           << " samples free of gaps or missing at most a tenth of each half (the longest stretch between them holds "
           << longest << " samples)\n";
    }
    if (rv) {
      const auto& q = rv->quantization;
      if (q.detected) os << "rounding step " << fmt(q.quantum) << " detected; flags are calibrated against it\n";
      int flagged = 0;
      for (const auto& d : rv->diagnostic) flagged += d.contaminated;
      if (flagged) os << flagged << " level(s) flagged as contaminated: there the robust WV is the one to trust\n";
      os << screening_summary(w, w.n, set.freq, set.freq_known);
      for (int j = 0; j < w.levels(); ++j)
        if (!w.notes[static_cast<std::size_t>(j)].empty() && !std::isfinite(w.wv[static_cast<std::size_t>(j)]))
          os << "level " << j + 1 << ": " << w.notes[static_cast<std::size_t>(j)] << '\n';
    }
  }
  return os.str();
}

std::string wv_csv(const io::SignalSet& set, const pipeline::WvStudy& study) {
  const bool robust = !study.columns.empty() && study.columns.front().robust.has_value();
  std::ostringstream os;
  os << "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients";
  if (robust) os << ",classical_wv,robust_to_classical,ci_disjoint,contaminated";
  os << "\n";
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const auto& w = study.columns[k].wv;
    for (int j = 0; j < w.levels(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      os << io::csv_field(set.signals[k].name) << ',' << (j + 1) << ',';
      num(os, w.tau[l]) << ',';
      num(os, w.tau[l] / set.freq) << ',';
      num(os, w.wv[l]) << ',';
      num(os, w.ci_low[l]) << ',';
      num(os, w.ci_high[l]) << ',';
      os << w.coefficients[l];
      if (robust) {
        const auto& d = study.columns[k].robust->diagnostic[l];
        os << ',';
        num(os, d.classical_wv) << ',';
        num(os, d.robust_to_classical) << ',' << (d.ci_disjoint ? "true" : "false") << ','
                                       << (d.contaminated ? "true" : "false");
      }
      os << '\n';
    }
  }
  return os.str();
}

// The Allan deviation table and its read-offs, per column.
std::string adev_text(const io::SignalSet& set, const pipeline::WvStudy& study, const std::vector<std::string>& units) {
  std::ostringstream os;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    if (!study.columns[k].allan) continue;
    const FigureReport& r = *study.columns[k].allan;
    const std::string unit = k < units.size() ? units[k] : std::string();
    const std::string gappy_edf = "the windows of 2m samples used (each half missing at most " +
                                  fmt(100.0 * kAllanMaxMissingShare) + "% of its samples, averaged over the rest)";
    os << '\n'
       << set.signals[k].name << ": overlapping Allan deviation, " << fmt(100.0 * (1.0 - r.adev.alpha))
       << "% CI (chi-square, edf = " << (r.adev.complete.empty() ? "(N - 2m + 1)" : gappy_edf) << " / 2m)"
       << (unit.empty() ? "" : ", in " + unit) << '\n';
    // With missing samples: each point's windows without one (complete) and those read that
    // miss some (partial), as the JSON's allan says.
    const bool gaps = r.adev.complete.size() == r.adev.size() && r.adev.partial.size() == r.adev.size();
    std::vector<std::string> head = {"m", "tau [s]", "ADEV", "CI low", "CI high", "edf"};
    if (gaps) head.insert(head.end(), {"complete", "partial"});
    TextTable t(head);
    for (std::size_t i = 0; i < r.adev.size(); ++i) {
      std::vector<std::string> row = {std::to_string(r.adev.m[i]), fmt(r.adev.tau[i]),     fmt(r.adev.adev[i]),
                                      fmt(r.adev.ci_low[i]),       fmt(r.adev.ci_high[i]), fmt(r.adev.edf[i], 4)};
      if (gaps) row.insert(row.end(), {std::to_string(r.adev.complete[i]), std::to_string(r.adev.partial[i])});
      t.add(row);
    }
    os << t.str();
    if (gaps)
      os << "complete: the windows of 2m samples without a missing sample; partial: those read that miss some\n";
    os << noise_figures_table(r.chosen, unit);
  }
  return os.str();
}

std::string adev_csv(const io::SignalSet& set, const pipeline::WvStudy& study) {
  std::ostringstream os;
  os << "column,m,tau_seconds,adev,ci_low,ci_high,edf\n";
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    if (!study.columns[k].allan) continue;
    const AllanDeviation& a = study.columns[k].allan->adev;
    for (std::size_t i = 0; i < a.size(); ++i) {
      os << io::csv_field(set.signals[k].name) << ',' << a.m[i] << ',';
      num(os, a.tau[i]) << ',';
      num(os, a.adev[i]) << ',';
      num(os, a.ci_low[i]) << ',';
      num(os, a.ci_high[i]) << ',';
      num(os, a.edf[i]) << '\n';
    }
  }
  return os.str();
}

}  // namespace gmwm::report
