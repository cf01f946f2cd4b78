#include "timestamp.h"

#include "gmwm/engine/number_text.h"

#include "gmwm/io/stamp_timing.h"

#include "gmwm/engine/error.h"
#include "gmwm/engine/samples.h"

#include <algorithm>
#include <bit>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>

namespace gmwm::io::detail {

namespace {

// Unit of a timestamp column whose name does not say it, from the size of the median
// step, assuming a rate in the range inertial sensors use (about 0.2 Hz to 10 kHz):
//   step >= 1e5 -> ns  (<= 10 kHz; read as us it would be <= 10 Hz)
//   step >= 100 -> us  (10 Hz .. 10 kHz)
//   step >= 5   -> ms  (10 Hz .. 200 Hz)
//   otherwise   -> s   (>= 0.2 Hz; so ms at 1 kHz, step 1, reads as 1 Hz: state the unit)
constexpr double kNanosecondStep = 1e5;
constexpr double kMicrosecondStep = 100.0;
constexpr double kMillisecondStep = 5.0;

// A first time in [1e9, 1e10) units of s/ms/us/ns is a Unix time between 2001 and 2286;
// the guess is kept only when it also gives a plausible median step (1 us .. 100 s).
constexpr double kUnixTimeLow = 1e9;
constexpr double kUnixTimeHigh = 1e10;
constexpr double kPlausibleStepLow = 1e-6;
constexpr double kPlausibleStepHigh = 100.0;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string format_duration(double seconds) {
  char buf[64];
  const double a = std::fabs(seconds);
  if (a != 0.0 && a < 1e-3)
    std::snprintf(buf, sizeof buf, "%.4g us", seconds * 1e6);
  else if (a != 0.0 && a < 1.0)
    std::snprintf(buf, sizeof buf, "%.4g ms", seconds * 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.4g s", seconds);
  return buf;
}

namespace {

std::string format_hz(double hz) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g Hz", hz);
  return buf;
}

}  // namespace

std::optional<TimeUnit> parse_time_unit(std::string_view text) {
  const std::string t = lower(trim(text));
  if (t == "s" || t == "sec" || t == "secs" || t == "second" || t == "seconds") return TimeUnit{1.0, "s"};
  if (t == "ms" || t == "msec" || t == "millisecond" || t == "milliseconds") return TimeUnit{1e-3, "ms"};
  if (t == "us" || t == "usec" || t == "\xC2\xB5s" || t == "\xCE\xBCs" || t == "microsecond" || t == "microseconds")
    return TimeUnit{1e-6, "us"};
  if (t == "ns" || t == "nsec" || t == "nanosecond" || t == "nanoseconds") return TimeUnit{1e-9, "ns"};
  if (t == "min" || t == "minute" || t == "minutes") return TimeUnit{60.0, "min"};
  if (t == "h" || t == "hour" || t == "hours") return TimeUnit{3600.0, "h"};
  return std::nullopt;
}

std::pair<std::string, std::string> split_unit(std::string_view name) {
  name = trim(name);
  const std::size_t open = name.find_first_of("[(");
  if (open == std::string_view::npos) return {std::string(name), ""};
  const char close = name[open] == '[' ? ']' : ')';
  const std::size_t end = name.find(close, open + 1);
  if (end == std::string_view::npos || end + 1 != name.size()) return {std::string(name), ""};
  return {std::string(trim(name.substr(0, open))), std::string(trim(name.substr(open + 1, end - open - 1)))};
}

namespace {

// A sensor's own stamps, labelled: gyro_timestamp, accel_time, timestamp_gyro, time_accel
// (a file whose stamp columns each stamp the columns to their right, issue 47). Not with the
// one-letter "t" (x_t is more often a value than a stamp), nor with a unit as the label.
bool labelled_stamp(std::string_view base) {
  static constexpr std::array<std::string_view, 4> kStamps = {"timestamp", "time", "stamp", "timestamps"};
  for (const std::string_view stamp : kStamps) {
    if (base.size() <= stamp.size() + 1) continue;
    const std::string_view head = base.substr(0, stamp.size()), tail = base.substr(base.size() - stamp.size());
    if (head == stamp && base[stamp.size()] == '_' && !parse_time_unit(base.substr(stamp.size() + 1))) return true;
    if (tail == stamp && base[base.size() - stamp.size() - 1] == '_') return true;
  }
  return false;
}

}  // namespace

std::optional<TimeUnit> timestamp_name(std::string_view name) {
  name = trim(name);
  while (!name.empty() && (name.front() == '#' || name.front() == '%')) name.remove_prefix(1);
  auto [base_raw, unit_text] = split_unit(name);
  std::string base = lower(base_raw);
  static constexpr std::array<std::string_view, 10> kNames = {
      "timestamp",          "time",      "t", "stamp", "time_stamp", "timestamps", "times", "header.stamp",
      "field.header.stamp", "time stamp"};
  auto known = [](std::string_view b) { return std::find(kNames.begin(), kNames.end(), b) != kNames.end(); };
  std::optional<TimeUnit> unit;
  if (!unit_text.empty()) unit = parse_time_unit(unit_text);
  if (!known(base)) {
    // Unit as a suffix: time_s, timestamp_ns, t_ms, "time s".
    const std::size_t sep = base.find_last_of("_ ");
    const bool unit_suffix = sep != std::string::npos && known(std::string_view(base).substr(0, sep)) &&
                             parse_time_unit(std::string_view(base).substr(sep + 1));
    if (unit_suffix) {
      unit = parse_time_unit(std::string_view(base).substr(sep + 1));
    } else if (!labelled_stamp(base)) {
      return std::nullopt;
    }
  }
  return unit ? *unit : TimeUnit{};
}

// The list of increasing steps of jittery stamps: in memory, or in a temporary file once
// the record is beyond the memory budget.
struct StepStatistics::Store {
  std::vector<double> memory;
  std::unique_ptr<SampleFileWriter> writer;
  Samples file;

  void push(double step, std::int64_t count) {
    if (writer) {
      for (std::int64_t i = 0; i < count; ++i) writer->append(&step, 1);
    } else {
      memory.insert(memory.end(), static_cast<std::size_t>(count), step);
    }
  }
  void to_file() {
    if (writer || file.in_file()) return;
    writer = std::make_unique<SampleFileWriter>();
    writer->append(memory.data(), memory.size());
    std::vector<double>().swap(memory);
  }
  bool in_file() const { return writer || file.in_file(); }
  // The steps in a file, once every one has been added.
  std::span<const double> file_view() {
    if (writer) {
      file = writer->finish();
      writer.reset();
    }
    return file;
  }
};

namespace {

// The k-th smallest (0-based) of positive finite doubles, exactly, in four passes over a
// series of any length (a radix selection on the bits, which order positive doubles as
// integers): for a list in a file, whose pages each pass releases (for_each_block).
double select_rank(std::span<const double> v, std::uint64_t k) {
  constexpr int kDigitBits = 16;
  std::vector<std::uint64_t> counts(std::size_t{1} << kDigitBits);
  std::uint64_t prefix = 0, mask = 0;
  for (int shift = 64 - kDigitBits; shift >= 0; shift -= kDigitBits) {
    std::fill(counts.begin(), counts.end(), 0);
    for_each_block(v, [&](std::span<const double> part, std::size_t) {
      for (double d : part) {
        const auto u = std::bit_cast<std::uint64_t>(d);
        if ((u & mask) == prefix) ++counts[(u >> shift) & 0xFFFF];
      }
    });
    std::uint64_t digit = 0;
    while (digit + 1 < counts.size() && k >= counts[digit]) k -= counts[digit++];
    prefix |= digit << shift;
    mask |= std::uint64_t{0xFFFF} << shift;
  }
  return std::bit_cast<double>(prefix);
}

// The mean of the middle half of a block (reordered in place).
double interquartile_mean(std::vector<double>& b) {
  const std::size_t n = b.size(), q1 = n / 4, q3 = n - n / 4;
  std::nth_element(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(q1), b.end());
  std::nth_element(b.begin() + static_cast<std::ptrdiff_t>(q1), b.begin() + static_cast<std::ptrdiff_t>(q3), b.end());
  double sum = 0.0;
  for (std::size_t i = q1; i < q3; ++i) sum += b[i];
  return sum / static_cast<double>(q3 - q1);
}

}  // namespace

StepStatistics::StepStatistics() {
  block_.reserve(kRateBlock);
  block_samples_.reserve(kRateBlock);
}
StepStatistics::~StepStatistics() = default;
StepStatistics::StepStatistics(StepStatistics&&) noexcept = default;
StepStatistics& StepStatistics::operator=(StepStatistics&&) noexcept = default;

void StepStatistics::add(double offset, double magnitude) {
  magnitude_ = std::max(magnitude_, magnitude);
  if (samples_++ == 0) {
    previous_ = offset;
    return;
  }
  const double d = offset - previous_;
  previous_ = offset;
  if (!(d > 0.0)) {
    ++disorder_;
    const std::int64_t sample = samples_ - 1;
    if (d == 0.0) {
      ++duplicated_;
      if (first_duplicated_ < 0) first_duplicated_ = sample;
      last_duplicated_ = sample;
    } else if (first_backward_ < 0) {
      first_backward_ = sample;
    }
    return;
  }
  if (block_.empty()) block_start_ = samples_ - 2;  // the sample the step starts from
  block_.push_back(d);
  block_samples_.push_back(samples_ - 1);
  block_offsets_.push_back(offset);
  if (block_.size() == kRateBlock) end_block();
  if (run_length_ > 0 && d == run_step_) {
    ++run_length_;
    return;
  }
  flush_run();
  run_step_ = d;
  run_length_ = 1;
}

void StepStatistics::keep_long_steps(double limit) const {
  for (std::size_t k = 0; k < block_.size(); ++k) {
    if (!(block_[k] > limit)) continue;
    if (candidates_.size() == kMaxGapCandidates) {
      candidates_kept_ = false;
      break;
    }
    candidates_.push_back({block_samples_[k], block_[k], block_offsets_[k]});
  }
}

void StepStatistics::end_block() const {
  scratch_.assign(block_.begin(), block_.end());
  const double typical = interquartile_mean(scratch_);
  // The block's spread below its median: gaps only lengthen steps, so the lower tail is the
  // stamps' jitter alone, whatever share of the steps (under half) are gaps.
  const auto q10 = static_cast<std::ptrdiff_t>(scratch_.size() / 10);
  const auto q50 = static_cast<std::ptrdiff_t>(scratch_.size() / 2);
  std::nth_element(scratch_.begin(), scratch_.begin() + q50, scratch_.end());
  const double median = scratch_[static_cast<std::size_t>(q50)];
  std::nth_element(scratch_.begin(), scratch_.begin() + q10, scratch_.begin() + q50);
  if (median > 0.0) block_spreads_.push_back((median - scratch_[static_cast<std::size_t>(q10)]) / median);
  keep_long_steps(kGapCandidateFactor * typical);
  block_.clear();
  block_samples_.clear();
  block_offsets_.clear();
  if (!have_first_) {
    have_first_ = true;
    first_typical_ = far_typical_ = typical;
    far_start_ = block_start_;
  } else if (std::fabs(std::log(typical / first_typical_)) > std::fabs(std::log(far_typical_ / first_typical_))) {
    far_typical_ = typical;
    far_start_ = block_start_;
  }
}

std::optional<RateChange> StepStatistics::rate_change() const {
  finish_blocks();
  if (!have_first_ || std::fabs(std::log(far_typical_ / first_typical_)) <= std::log(kRateChangeRatio))
    return std::nullopt;
  return RateChange{first_typical_, far_typical_, 0, far_start_};
}

void StepStatistics::finish_blocks() const {
  if (block_.size() >= kRateBlockMin) {
    end_block();
  } else if (!block_.empty()) {
    // Too few steps for a typical step of their own: every step of the last, short block is
    // a candidate (at most kRateBlockMin), judged against the median by long_steps.
    keep_long_steps(0.0);
    block_.clear();
    block_samples_.clear();
    block_offsets_.clear();
  }
}

double StepStatistics::jitter() const {
  finish_blocks();
  if (block_spreads_.empty()) return 0.0;
  std::vector<double> v = block_spreads_;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::vector<StepStatistics::LongStep> StepStatistics::long_steps(double limit) const {
  finish_blocks();
  std::vector<LongStep> out;
  for (const LongStep& c : candidates_)
    if (c.step > limit) out.push_back(c);
  return out;
}

void StepStatistics::spill_to_file() {
  to_file_ = true;
  if (spilled_) spilled_->to_file();
}

void StepStatistics::flush_run() const {
  if (run_length_ == 0) return;
  if (spilled_) {
    spilled_->push(run_step_, run_length_);
  } else {
    counts_[run_step_] += run_length_;
    if (counts_.size() > kMaxDistinctSteps) {
      spilled_ = std::make_unique<Store>();
      if (to_file_) spilled_->to_file();
      for (const auto& [step, count] : counts_) spilled_->push(step, count);
      counts_ = {};
    }
  }
  run_length_ = 0;
}

double StepStatistics::median() const {
  flush_run();
  if (spilled_ && spilled_->in_file()) {
    const std::span<const double> v = spilled_->file_view();
    if (v.empty()) return 0.0;
    const std::uint64_t mid = v.size() / 2;
    const double hi = select_rank(v, mid);
    if (v.size() % 2 == 1) return hi;
    return 0.5 * (select_rank(v, mid - 1) + hi);
  }
  if (spilled_) {
    std::vector<double>& v = spilled_->memory;  // reordered in place; the multiset is unchanged
    if (v.empty()) return 0.0;
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    const double hi = v[mid];
    if (v.size() % 2 == 1) return hi;
    const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
    return 0.5 * (lo + hi);
  }
  std::vector<std::pair<double, std::int64_t>> sorted(counts_.begin(), counts_.end());
  if (sorted.empty()) return 0.0;
  std::sort(sorted.begin(), sorted.end());
  std::int64_t total = 0;
  for (const auto& e : sorted) total += e.second;
  // The steps at 0-based ranks mid - 1 and mid of the sorted list.
  const std::int64_t mid = total / 2;
  auto at_rank = [&](std::int64_t r) {
    std::int64_t seen = 0;
    for (const auto& [step, count] : sorted) {
      seen += count;
      if (r < seen) return step;
    }
    return sorted.back().first;
  };
  const double hi = at_rank(mid);
  if (total % 2 == 1) return hi;
  return 0.5 * (at_rank(mid - 1) + hi);
}

std::pair<std::int64_t, double> StepStatistics::above(double limit) const {
  flush_run();
  std::int64_t n = 0;
  double largest = 0.0;
  auto visit = [&](double step, std::int64_t count) {
    if (step > limit) {
      n += count;
      largest = std::max(largest, step);
    }
  };
  if (spilled_ && spilled_->in_file()) {
    for_each_block(spilled_->file_view(), [&](std::span<const double> part, std::size_t) {
      for (double d : part) visit(d, 1);
    });
  } else if (spilled_) {
    for (double d : spilled_->memory) visit(d, 1);
  } else {
    for (const auto& [step, count] : counts_) visit(step, count);
  }
  return {n, largest};
}

void check_timestamp_rate(const std::string& path, const TimingReport& timing, const ReadOptions& options) {
  if (options.freq) return;
  if (timing.estimated_freq > 0.0 &&
      timing.resolution_seconds > TimingReport::kDisagreement * timing.median_step_seconds) {
    char share[32];
    std::snprintf(share, sizeof share, "%g%%", 100.0 * TimingReport::kDisagreement);
    throw InputError(
        path + ": timestamps '" + timing.column + "' in " + timing.unit + " (" + timing.unit_source +
        "): median step " + format_duration(timing.median_step_seconds) + " = " + format_hz(timing.estimated_freq) +
        ", but doubles hold stamps near " + format_duration(timing.largest_stamp_seconds) + " only to " +
        format_duration(timing.resolution_seconds) + ", too coarse to resolve the sampling rate (to " + share +
        " it needs steps of at least " + format_duration(timing.resolution_seconds / TimingReport::kDisagreement) +
        "); give --freq HZ, or write the stamps relative to the start or as integer nanoseconds");
  }
  if (timing.estimated_freq > 0.0 && !sampling_rate_problem(timing.estimated_freq, "").empty())
    throw InputError(path + ": timestamps '" + timing.column + "' in " + timing.unit + " (" + timing.unit_source +
                     "): median step " + format_duration(timing.median_step_seconds) + " = " +
                     format_hz(timing.estimated_freq) + ", expected " + sampling_rate_expected() +
                     "; give --freq HZ to set the rate");
  if (!timing.rate_change) return;
  throw InputError(path + ": timestamps '" + timing.column + "': " + timing.rate_change_text() +
                   ", expected one rate (a wavelet variance's scales are counted in samples): split the record "
                   "there, or give --freq HZ to take the samples as evenly spaced");
}

void refuse_never_increasing(const std::string& path, const TimingReport& timing) {
  throw InputError(path + ": found timestamps in column '" + timing.column +
                   "' that never increase, expected increasing times; give the sampling rate with --freq HZ");
}

TimingReport analyse_timing(const std::string& column, const std::vector<double>& offsets, double first_time,
                            const TimeUnit& unit, const std::string& unit_source) {
  StepStatistics steps;
  for (double t : offsets) steps.add(t);
  return analyse_timing(column, steps, first_time, unit, unit_source);
}

namespace {

// Where the gaps are and how many samples each lost: round(step / median) - 1, on the grid
// of the record's samples with the missing ones between them. A step further than
// kGapLengthTolerance from a whole number of median steps is a gap of unknown length.
void place_gaps(const StepStatistics& steps, double median, TimingReport& r) {
  const std::vector<StepStatistics::LongStep> gaps = steps.long_steps(TimingReport::kGapFactor * median);
  r.gap_positions_known = steps.gap_positions_kept() && static_cast<std::int64_t>(gaps.size()) == r.gaps;
  r.jitter = steps.jitter();
  if (!r.gap_positions_known) return;
  std::int64_t before = 0;  // missing samples before the current gap
  for (const StepStatistics::LongStep& g : gaps) {
    const double periods = g.step / median;
    const double whole = std::round(periods);
    if (std::fabs(periods - whole) > TimingReport::kGapLengthTolerance) {
      if (r.uncertain_gaps++ == 0)
        r.first_uncertain_gap = {g.sample, g.step * r.unit_to_seconds, (g.offset - g.step) * r.unit_to_seconds,
                                 g.offset * r.unit_to_seconds};
      continue;
    }
    const auto lost = static_cast<std::int64_t>(whole) - 1;
    r.missing.push_back({g.sample + before, lost});
    before += lost;
  }
}

}  // namespace

TimingReport analyse_timing(const std::string& column, const StepStatistics& steps, double first_time,
                            const TimeUnit& unit, const std::string& unit_source) {
  TimingReport r;
  r.column = column;
  r.samples = steps.samples();
  r.disorder = steps.disorder();
  r.duplicated = steps.duplicated();
  r.first_duplicated = steps.first_duplicated();
  r.last_duplicated = steps.last_duplicated();
  r.first_backward = steps.first_backward();
  const double step = steps.median();  // in the file's unit
  if (unit.to_seconds > 0.0) {
    r.unit_to_seconds = unit.to_seconds;
    r.unit = unit.label;
    r.unit_source = unit_source;
  } else {
    static const TimeUnit kUnits[] = {{1.0, "s"}, {1e-3, "ms"}, {1e-6, "us"}, {1e-9, "ns"}};
    for (const TimeUnit& u : kUnits) {
      const double t = first_time * u.to_seconds;
      const double s = step * u.to_seconds;
      if (t >= kUnixTimeLow && t < kUnixTimeHigh && s >= kPlausibleStepLow && s <= kPlausibleStepHigh) {
        r.unit_to_seconds = u.to_seconds;
        r.unit = u.label;
        r.unit_source = "the first time looks like a Unix time";
      }
    }
    if (r.unit.empty()) {
      const TimeUnit& u = step >= kNanosecondStep    ? kUnits[3]
                          : step >= kMicrosecondStep ? kUnits[2]
                          : step >= kMillisecondStep ? kUnits[1]
                                                     : kUnits[0];
      r.unit_to_seconds = u.to_seconds;
      r.unit = u.label;
      r.unit_source = "guessed from the median step; state it in the header, e.g. 'time [s]'";
    }
  }
  r.median_step_seconds = step * r.unit_to_seconds;
  if (const double m = steps.largest_magnitude(); m > 0.0) {
    r.largest_stamp_seconds = m * r.unit_to_seconds;
    r.resolution_seconds = (std::nextafter(m, std::numeric_limits<double>::infinity()) - m) * r.unit_to_seconds;
  }
  r.estimated_freq = step > 0.0 ? 1.0 / r.median_step_seconds : 0.0;
  if (const std::optional<RateChange> c = steps.rate_change()) {
    r.rate_change = TimingReport::RateChange{1.0 / (c->from_step * r.unit_to_seconds),
                                             1.0 / (c->to_step * r.unit_to_seconds), c->to_sample};
  }
  if (step > 0.0) {
    const auto [gaps, largest] = steps.above(TimingReport::kGapFactor * step);
    r.gaps = gaps;
    r.largest_gap_seconds = largest * r.unit_to_seconds;
    if (gaps > 0) place_gaps(steps, step, r);
  }
  return r;
}

}  // namespace gmwm::io::detail

namespace gmwm::io {

std::string TimingReport::summary() const {
  using detail::format_duration;
  using detail::format_hz;
  std::string s = "timestamps '" + column + "' in " + unit + " (" + unit_source + "): ";
  if (estimated_freq > 0.0) {
    s += "median step " + format_duration(median_step_seconds) + " = " + format_hz(estimated_freq) + ", " +
         std::to_string(gaps) + (gaps == 1 ? " gap" : " gaps");
    if (gaps > 0) s += " (largest " + format_duration(largest_gap_seconds) + ")";
  } else {
    s += "the times never increase";
  }
  s += ", " + std::to_string(disorder) + " out of order";
  if (const std::string d = disorder_text(); !d.empty()) s += " (" + d + ")";
  if (rate_change) s += "; " + rate_change_text();
  if (given_freq && estimated_freq > 0.0) {
    const double rel = std::fabs(estimated_freq - *given_freq) / *given_freq;
    if (rel > kDisagreement) {
      char pct[32];
      std::snprintf(pct, sizeof pct, "%.3g%%", 100.0 * rel);
      s += "; --freq " + format_hz(*given_freq) + " disagrees with them by " + pct + " (--freq is used)";
    }
  }
  return s;
}

std::string TimingReport::disorder_text() const {
  if (disorder == 0) return {};
  std::string s;
  if (duplicated > 0) {
    char share[32];
    std::snprintf(share, sizeof share, "%.3g%%",
                  100.0 * static_cast<double>(duplicated) / static_cast<double>(samples));
    s = std::to_string(duplicated) + (duplicated == 1 ? " repeats" : " repeat") + " the stamp before (" + share +
        " of the samples, " +
        (first_duplicated == last_duplicated
             ? "at sample " + std::to_string(first_duplicated)
             : "from sample " + std::to_string(first_duplicated) + " to " + std::to_string(last_duplicated)) +
        ")";
  }
  if (const std::int64_t backward = disorder - duplicated; backward > 0)
    s += (s.empty() ? "" : ", ") + std::to_string(backward) + (backward == 1 ? " goes" : " go") +
         " backwards (first at sample " + std::to_string(first_backward) + ")";
  return s;
}

std::string TimingReport::rate_change_text() const {
  if (!rate_change) return {};
  using detail::format_hz;
  return "the sampling rate changes within the record, from about " + format_hz(rate_change->from_hz) +
         " at its start to about " + format_hz(rate_change->to_hz) + " from sample " +
         std::to_string(rate_change->sample + 1);
}

TimingReport timing_of_stamps(std::span<const std::int64_t> stamps_ns, const std::string& source,
                              const std::string& column, std::optional<double> freq) {
  detail::StepStatistics steps;
  // Offsets from the first stamp, subtracted as integers: exact (a step's spacing is the
  // nanosecond however far the stamps are from their origin).
  const std::int64_t first = stamps_ns.empty() ? 0 : stamps_ns.front();
  for (const std::int64_t t : stamps_ns) {
    std::int64_t offset = 0;
    if (__builtin_sub_overflow(t, first, &offset))  // stamps 292 years apart: none a sensor gives
      throw InputError(source + ": timestamps '" + column + "': found " + std::to_string(t) + " ns after " +
                       std::to_string(first) + " ns, expected times within 292 years of the first");
    steps.add(static_cast<double>(offset));
  }
  TimingReport timing = detail::analyse_timing(column, steps, static_cast<double>(first), detail::TimeUnit{1e-9, "ns"},
                                               "integer nanoseconds");
  timing.given_freq = freq;
  ReadOptions options;
  options.freq = freq;
  detail::check_timestamp_rate(source, timing, options);
  if (!freq && !(timing.estimated_freq > 0.0)) detail::refuse_never_increasing(source, timing);
  return timing;
}

}  // namespace gmwm::io
