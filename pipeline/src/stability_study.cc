// The frequency-stability study: checks -> each column as phase -> each kind's deviation at
// its factors (stability_study.h).
#include "gmwm/pipeline/stability_study.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

#include "column_wvs.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::pipeline {
namespace {

// The kinds that read a phase in a temporary file in pieces, holding memory that does not
// grow with the record (deviation.h); the others keep working arrays as long as it.
bool reads_in_bounded_memory(stability::DeviationKind kind) {
  using K = stability::DeviationKind;
  switch (kind) {
    case K::kAdev:
    case K::kOadev:
    case K::kMdev:
    case K::kTdev:
    case K::kHdev:
    case K::kOhdev:
    case K::kTotdev:
    case K::kTierms:
      return true;
    default:
      return false;
  }
}

std::string file_place(const io::SignalSet& set) { return set.path.empty() ? std::string() : set.path + ": "; }

// The averaging factors of --taus LIST: each tau a whole number of the kind's step (the
// sampling period; Theo1's 0.75 of it: tau = 0.75 m tau0), within `top`.
std::vector<std::int64_t> listed_factors(const std::vector<double>& taus, double tau0, std::int64_t top,
                                         stability::DeviationKind kind, std::int64_t phase_points) {
  const double step = stability::averaging_time(kind, 1, tau0);
  const std::string what =
      step == tau0 ? "sampling periods of " + significant(tau0, 9) + " s"
                   : std::string(stability::deviation_name(kind)) + "'s steps of " + significant(step, 9) + " s";
  std::vector<std::int64_t> m;
  for (const double tau : taus) {
    const double periods = tau / step;
    const double whole = std::round(periods);
    if (!(whole >= 1.0) || std::abs(periods - whole) > kWholePeriodTolerance * whole)
      throw InputError("--taus: " + significant(tau, 9) + " s is not a whole number of " + what);
    if (whole > static_cast<double>(top))  // compared as doubles: 1e300 periods fit no integer
      throw InputError("--taus: " + significant(tau, 9) + " s is " + significant(whole, 9) + " periods, beyond " +
                       std::string(stability::deviation_name(kind)) + "'s largest " + std::to_string(top) + " on " +
                       std::to_string(phase_points) + " phase points (" + significant(top * step, 9) + " s)");
    if (!m.empty() && static_cast<std::int64_t>(whole) == m.back())
      throw InputError("--taus: " + significant(tau, 15) + " s is the averaging factor " + significant(whole, 9) +
                       " again (" + significant(whole * step, 9) + " s)");
    m.push_back(static_cast<std::int64_t>(whole));
  }
  return m;
}

// The study's steps (each factor's deviation, each kind's intervals) told to the options'
// progress as they are done.
struct Steps {
  const std::function<void(int, int)>& progress;
  int done = 0, total = 0;
  void tick() {
    ++done;
    if (progress) progress(done, total);
  }
};

// One series' deviations of every kind asked, with their intervals (their wall time added to
// `interval_seconds`): the rate `y` less its mean, as phase.
StabilityColumn study_column(const io::SignalSet& set, const std::string& name, const Samples& y,
                             const StabilityStudyOptions& options, double tau0, double& interval_seconds,
                             Steps& steps) {
  if (y.in_file())
    for (const stability::DeviationKind kind : options.kinds)
      if (!reads_in_bounded_memory(kind))
        throw InputError(file_place(set) + "column '" + name + "': its " + std::to_string(y.size()) +
                         " samples are beyond the memory budget (--memory), and " +
                         std::string(stability::deviation_name(kind)) +
                         " keeps working arrays as long as the record in memory; the kinds read in bounded memory "
                         "are adev, oadev, mdev, tdev, hdev, ohdev, totdev and tierms (or raise --memory)");
  const Samples phase = stability::phase_from_record(y, tau0);  // less its mean
  const auto phase_points = static_cast<std::int64_t>(phase.size());
  StabilityColumn column{name, {}, {}};
  for (const stability::DeviationKind kind : options.kinds) {
    const std::int64_t top = stability::max_factor(kind, phase_points);
    const std::vector<std::int64_t> m = options.tau_list.empty()
                                            ? stability::factors(options.taus, kind, phase_points)
                                            : listed_factors(options.tau_list, tau0, top, kind, phase_points);
    if (m.empty())
      throw InputError(file_place(set) + "column '" + name + "': " + std::to_string(y.size()) + " samples leave " +
                       std::string(stability::deviation_name(kind)) + " no averaging time");
    column.deviations.push_back(
        stability::deviation(kind, phase, tau0, m, [&](std::size_t, std::size_t) { steps.tick(); }));
    const auto intervals_start = std::chrono::steady_clock::now();
    column.intervals.push_back(stability::deviation_intervals(column.deviations.back(), phase, options.intervals));
    interval_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - intervals_start).count();
    steps.tick();
  }
  return column;
}

// a - b, in a temporary file when a is in one (a record beyond the memory budget), both
// released behind the pass.
Samples difference_of(const Samples& a, const Samples& b) {
  std::optional<SampleFileWriter> file;
  std::vector<double> memory;
  if (a.in_file())
    file.emplace();
  else
    memory.reserve(a.size());
  std::vector<double> block;
  for_each_block(a, [&](std::span<const double> part, std::size_t at) {
    block.resize(part.size());
    for (std::size_t i = 0; i < part.size(); ++i) block[i] = part[i] - b[at + i];
    gmwm::detail::release_file_pages(b.data() + at, b.data() + at + part.size());
    if (file)
      file->append(block.data(), block.size());
    else
      memory.insert(memory.end(), block.begin(), block.end());
  });
  return file ? file->finish() : Samples(std::move(memory));
}

// The three-cornered hat of the set's three columns: the pairs A - B, B - C, C - A studied as
// columns are (differences of rates recorded together: what the sensors share cancels), then
// each kind's separation.
StabilityHat study_hat(const io::SignalSet& set, const StabilityStudyOptions& options, double tau0,
                       double& interval_seconds, Steps& steps) {
  StabilityHat hat;
  for (std::size_t k = 0; k < stability::kHatSensors; ++k) hat.sensors[k] = set.signals[k].name;
  for (std::size_t k = 0; k < stability::kHatSensors; ++k) {
    const std::size_t next = (k + 1) % stability::kHatSensors;
    const Samples difference = difference_of(set.signals[k].values, set.signals[next].values);
    hat.pairs.push_back(study_column(set, hat.sensors[k] + " - " + hat.sensors[next], difference, options, tau0,
                                     interval_seconds, steps));
  }
  for (std::size_t d = 0; d < options.kinds.size(); ++d) {
    const std::array<stability::DeviationCurve, stability::kHatSensors> curves = {
        hat.pairs[0].deviations[d], hat.pairs[1].deviations[d], hat.pairs[2].deviations[d]};
    const std::array<stability::DeviationIntervals, stability::kHatSensors> intervals = {
        hat.pairs[0].intervals[d], hat.pairs[1].intervals[d], hat.pairs[2].intervals[d]};
    hat.kinds.push_back(stability::three_cornered_hat(curves, intervals));
  }
  return hat;
}

}  // namespace

std::string StabilityStudyOptions::Validate() const {
  if (kinds.empty()) return "--kind: expected at least one deviation";
  for (std::size_t i = 0; i < kinds.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (kinds[i] == kinds[j]) return "--kind: " + std::string(stability::deviation_name(kinds[i])) + " given twice";
  // The interval options' fields as the command spells them.
  if (std::string why = intervals.Validate(); !why.empty())
    return why.starts_with("noise_alpha") ? "--noise-alpha" + why.substr(11) : "--" + why;
  if (three_cornered_hat)
    for (const stability::DeviationKind k : kinds)
      if (!stability::separable(k))
        return "--hat: " + std::string(stability::deviation_name(k)) +
               " is a maximum, not a variance: the three-cornered hat separates every kind but mtie";
  for (std::size_t i = 0; i < tau_list.size(); ++i) {
    if (!(tau_list[i] > 0.0) || !std::isfinite(tau_list[i]))
      return "--taus: found " + significant(tau_list[i], 9) + ", expected positive averaging times in seconds";
    if (i > 0 && !(tau_list[i] > tau_list[i - 1]))
      return "--taus: expected increasing averaging times, found " + significant(tau_list[i], 9) + " s after " +
             significant(tau_list[i - 1], 9) + " s";
  }
  return {};
}

namespace {

// Every factor of the kinds asked (--taus all) within kMaxAllTausWork points read; beyond,
// refused naming the work and what reads less.
void require_all_taus_within_work(const io::SignalSet& set, const StabilityStudyOptions& options,
                                  std::int64_t phase_points) {
  if (!options.tau_list.empty() || options.taus != stability::TauSet::kAll) return;
  double work = 0.0;
  std::size_t count = 0;
  for (const stability::DeviationKind kind : options.kinds) {
    const std::vector<std::int64_t> m = stability::factors(stability::TauSet::kAll, kind, phase_points);
    count += m.size();
    for (const std::int64_t f : m) work += stability::factor_work(kind, phase_points, f);
  }
  if (work <= kMaxAllTausWork) return;
  throw InputError(file_place(set) + "--taus all: the " + std::to_string(count) + " averaging factors of " +
                   std::to_string(phase_points) + " phase points read " + significant(work, 2) +
                   " points, beyond the " + significant(kMaxAllTausWork, 2) +
                   " read for every factor (about 3.5 minutes); give octave, decade, a list of times or fewer kinds");
}

}  // namespace

void require_hat_columns(const io::SignalSet& set) {
  if (set.signals.size() == stability::kHatSensors) return;
  std::string names;
  for (const io::Signal& s : set.signals) names += (names.empty() ? "" : ", ") + s.name;
  throw InputError(file_place(set) +
                   "--hat: the three-cornered hat reads three columns recorded together (--columns A,B,C), found " +
                   std::to_string(set.signals.size()) + (names.empty() ? std::string() : " (" + names + ")"));
}

StabilityStudy study_stability(const io::SignalSet& set, const StabilityStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  if (!set.freq_known)
    throw InputError(file_place(set) +
                     "the stability deviations need the sampling rate: give --freq HZ or a timestamp column");
  detail::require_regular(set, "gmwm stability");
  if (options.three_cornered_hat) require_hat_columns(set);
  const std::int64_t phase_points =
      set.signals.empty() ? 0 : static_cast<std::int64_t>(set.signals.front().values.size()) + 1;
  require_all_taus_within_work(set, options, phase_points);
  const auto start = std::chrono::steady_clock::now();
  StabilityStudy study;
  study.tau0 = 1.0 / set.freq;
  study.phase_points = phase_points;
  Steps steps{options.progress};
  for (const stability::DeviationKind kind : options.kinds) {  // each factor, then the kind's intervals
    const auto factors = options.tau_list.empty() ? stability::factors(options.taus, kind, phase_points).size()
                                                  : options.tau_list.size();
    steps.total += static_cast<int>(factors) + 1;
  }
  steps.total *= static_cast<int>(set.signals.size() + (options.three_cornered_hat ? stability::kHatSensors : 0));
  for (const io::Signal& s : set.signals)
    study.columns.push_back(study_column(set, s.name, s.values, options, study.tau0, study.interval_seconds, steps));
  if (options.three_cornered_hat) study.hat = study_hat(set, options, study.tau0, study.interval_seconds, steps);
  study.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - study.interval_seconds;
  return study;
}

}  // namespace gmwm::pipeline
