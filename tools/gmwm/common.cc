#include "common.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include "gmwm/pipeline/first_level.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/choice.h"
#include "gmwm/io/read_request.h"
#include "gmwm/robust/robust_request.h"

namespace gmwm::cli {

std::optional<double> parse_decimal(std::string_view text) {
  if (text.empty()) return std::nullopt;
  // from_chars takes no '+'; it takes "inf" and "nan", refused below, and never hex.
  if (text.front() == '+') text.remove_prefix(1);
  if (text.empty() ||
      !(std::isdigit(static_cast<unsigned char>(text.front())) || text.front() == '.' || text.front() == '-'))
    return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v, std::chars_format::general);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

CLI::Validator whole_number(std::uint64_t lo, std::uint64_t hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        std::uint64_t v = 0;
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (!digits || ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
          return "found '" + text + "', expected an integer from " + range;
        text = std::to_string(v);
        return "";
      },
      range);
}

CLI::Validator choice_of(std::vector<std::string> names) {
  std::string listed;
  for (const std::string& n : names) listed += (listed.empty() ? "" : ",") + n;
  return CLI::Validator(
      [names](std::string& text) -> std::string {
        return std::find(names.begin(), names.end(), text) != names.end() ? "" : unknown_choice(text, names);
      },
      "{" + listed + "}");
}

CLI::Option* add_choice(CLI::App& sub, const std::string& name, std::string& target,
                        const std::vector<std::string>& names, const std::string& help) {
  return sub.add_option(name, target, help + ": " + in_words(names))->check(choice_of(names))->capture_default_str();
}

CLI::Validator decimal_number(std::function<bool(double)> accept, std::string expected) {
  return CLI::Validator(
      [accept = std::move(accept), expected](std::string& text) -> std::string {
        const std::optional<double> v = parse_decimal(text);
        if (!v || !accept(*v)) return "found '" + text + "', expected " + expected;
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", *v);
        text = buf;
        return "";
      },
      "");
}

CLI::Validator decimal_number(std::string expected) {
  return decimal_number([](double) { return true; }, std::move(expected));
}

CLI::Validator sampling_rate_number() {
  char expected[96];
  std::snprintf(expected, sizeof expected, "a sampling rate in Hz from %g to %g", io::kMinFreq, io::kMaxFreq);
  return decimal_number([](double f) { return io::sampling_rate_problem(f, "").empty(); }, expected);
}

CLI::Validator memory_megabytes() {
  return decimal_number([](double mb) { return io::memory_problem(mb, "").empty(); }, io::memory_expected());
}

void add_common_options(CLI::App& sub, CommonOptions& common) {
  sub.add_option("--json", common.json, "Write the machine-readable result to PATH ('-' for standard output)")
      ->type_name("PATH");
  sub.add_option("--threads", common.threads, "Worker threads (default: all cores)")
      ->type_name("N")
      ->transform(whole_number(1, 4096));
  sub.add_option("--seed", common.seed, "Random seed (default fixed, so runs are reproducible)")
      ->type_name("S")
      ->transform(whole_number(0, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  sub.add_flag("--quiet,-q", common.quiet, "No result table on the terminal (errors and warnings still go to stderr)");
  sub.add_flag("--verbose,-v", common.verbose,
               "Every table on the terminal (fit, select: the ranking, continuous parameters, noise figures and "
               "Kalman terms after the per-axis summary)");
  sub.add_option("--log-level", common.log_level,
                 "Library log level on stderr (the command reports fit statuses itself)")
      ->type_name("LEVEL")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
}

// A CLI11 check that is the library's rule for an option's text: its message without the
// option's name, which CLI11 puts in front.
template <typename T>
std::function<std::string(const std::string&)> library_rule(T (*of)(const std::string&), std::string prefix) {
  return [of, prefix](const std::string& text) {
    try {
      of(text);
      return std::string();
    } catch (const InputError& e) {
      const std::string m = e.what();
      return m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : m;
    }
  };
}

// --gaps, --data, --decimate, --decimate-filter: what reading does with the samples (issue 47).
void add_conditioning_options(CLI::App& sub, InputOptions& input) {
  sub.add_option("--gaps", input.gaps,
                 "Samples the timestamps show missing: 'windows' reads each scale from the windows that hold none "
                 "(a gap of unknown length is refused), 'join' joins the samples end to end as if none were "
                 "missing")
      ->type_name("windows|join")
      ->check(library_rule<io::GapHandling>(io::gap_handling_of, "--gaps: "))
      ->capture_default_str();
  sub.add_option("--data", input.data,
                 "What each sample is: 'rate' (angular rate, specific force, fractional frequency), 'increment' "
                 "(a delta-angle or delta-velocity over one period, read as increment x rate) or 'phase' (a phase "
                 "or time error, an angle: read as its first differences x rate)")
      ->type_name("rate|increment|phase")
      ->check(library_rule<io::DataKind>(io::data_kind_of, "--data: "))
      ->capture_default_str();
  sub.add_option("--decimate", input.decimate,
                 "Keep one sample in K, after the filter of --decimate-filter; the rate becomes rate / K")
      ->type_name("K")
      ->transform(whole_number(1, io::kMaxDecimation));
  sub.add_option("--decimate-filter", input.decimate_filter,
                 "The anti-alias filter of --decimate: 'average' (the mean of each K samples; N, K, B of the band "
                 "kept are unchanged) or 'none' (every K-th sample: the band above folds in, N grows sqrt(K))")
      ->type_name("average|none")
      ->check(library_rule<io::DecimationFilter>(io::decimation_filter_of, "--decimate-filter: "))
      ->capture_default_str();
}

namespace {

// INPUT, --topic, --columns, --freq: where the record is and which of it.
void add_source_options(CLI::App& sub, InputOptions& input) {
  sub.add_option("INPUT", input.input,
                 "Delimited text file (CSV/TSV/semicolon/whitespace, optionally gzip) with a "
                 "header row, a PX4 ULog flight log (.ulg), a ROS 1 bag (.bag) or a ROS 2 bag (sqlite3 .db3 or "
                 "MCAP .mcap); see --topic")
      ->required();
  sub.add_option("--topic", input.topic,
                 "The IMU topic of a log: PX4 ULog sensor_combined (default), sensor_gyro or sensor_accel "
                 "(NAME:K for instance K); ROS bags: a sensor_msgs Imu topic (default: the only one). wv, fit, "
                 "select: A,B reads several topics, each at its own rate (the gyroscope and the accelerometer "
                 "on topics of their own)")
      ->type_name("NAME[:K][,...]");
  sub.add_option_function<std::string>(
         "--columns", [&input](const std::string& c) { input.columns = c; },
         "Columns to use: names or 1-based indices, comma-separated (default: every "
         "numeric column that is not a timestamp)")
      ->type_name("A,B,C");
  sub.add_option_function<double>(
         "--freq", [&input](const double& f) { input.freq = f; },
         "Sampling rate in Hz (required when the file has no timestamp column)")
      ->type_name("HZ")
      ->transform(sampling_rate_number());
}

// --memory and the conditioning (--gaps, --data, --decimate): how the record is read.
void add_reading_options(CLI::App& sub, InputOptions& input) {
  sub.add_option("--memory", input.memory_mb,
                 "Memory for the samples in MB (default: 75% of physical memory, at 16 bytes a value); a longer "
                 "record goes on in temporary files in $TMPDIR (8 bytes a value on disk) and the classical WV, fit, "
                 "select and stability then use memory that no longer grows with it")
      ->type_name("MB")
      ->transform(memory_megabytes());
  add_conditioning_options(sub, input);
}

}  // namespace

void add_record_options(CLI::App& sub, InputOptions& input) {
  add_source_options(sub, input);
  add_reading_options(sub, input);
}

void add_input_options(CLI::App& sub, InputOptions& input) {
  add_source_options(sub, input);
  sub.add_option("--alpha", input.alpha, "Confidence intervals at level 1 - alpha")
      ->transform(decimal_number([](double a) { return a >= kMinAlpha && a < 1.0; },
                                 "a number from 1e-10 to below 1 (the intervals' level is 1 - alpha)"))
      ->capture_default_str();
  sub.add_option("--levels", input.levels, "Number of WV levels J (default: floor(log2 N))")
      ->type_name("J")
      ->transform(whole_number(1, kMaxLevelsOption));
  add_reading_options(sub, input);
}

void add_robust_options(CLI::App& sub, RobustOptions& robust) {
  sub.add_flag("--robust", robust.robust,
               "Robust WV: M-estimator of each level's scale (Huber's Proposal 2, Fisher-consistent)");
  sub.add_option_function<double>(
         "--eff", [&robust](const double& e) { robust.eff = e; },
         "Gaussian efficiency of the robust WV, in (0, 1) (default 0.6); needs --robust")
      ->type_name("EFF")
      ->transform(decimal_number("a Gaussian efficiency strictly between 0 and 1 (e.g. 0.6)"));
  sub.add_option_function<std::string>(
         "--estimator", [&robust](const std::string& e) { robust.estimator = e; },
         "Robust estimator: huber (default) or bisquare; needs --robust")
      ->type_name("NAME");
  sub.add_flag("--no-spike-screen", robust.no_spike_screen,
               "Keep isolated spikes in the series (by default the robust WV replaces them first); needs --robust");
}

void add_fitting_options(CLI::App& sub, std::string& first_level, int& max_evaluations) {
  add_max_evaluations_option(sub, max_evaluations);
  add_first_level_option(sub, first_level,
                         "Fit the WV from this level on (tau = 2^L samples), the finer levels shown, not fitted");
}

void add_first_level_option(CLI::App& sub, std::string& first_level, const std::string& what) {
  sub.add_option("--first-level", first_level,
                 what +
                     ": auto starts above the scales that held or interpolated samples bias (the warning's "
                     "levels), 1 where a column's samples do not repeat")
      ->type_name("L|auto")
      ->check(CLI::Validator(
          [](std::string& given) -> std::string {
            return pipeline::parse_first_level(given)
                       ? ""
                       : "found '" + given + "', expected " + pipeline::kFirstLevelExpected;
          },
          "L|auto"))
      ->capture_default_str();
}

int first_level_of(const std::string& text) { return pipeline::parse_first_level(text).value_or(1); }

void add_max_evaluations_option(CLI::App& sub, int& max_evaluations) {
  sub.add_option("--max-evaluations", max_evaluations, "Objective evaluations per local optimisation before giving up")
      ->type_name("N")
      ->transform(whole_number(10, 100000000))
      ->capture_default_str();
}

std::optional<robust::RobustWvOptions> robust_wv_options(const RobustOptions& robust, const WvOptions& wv) {
  return robust::robust_wv_options({robust.robust, robust.eff, robust.estimator, robust.no_spike_screen}, wv);
}

std::shared_ptr<void> apply_common_options(const CommonOptions& common) {
  // The libraries log through the logger named "gmwm" (or the default one): both go to
  // stderr, so that stdout carries only the table or the JSON.
  auto logger = spdlog::get("gmwm");
  if (!logger) logger = spdlog::stderr_color_mt("gmwm");
  logger->set_pattern("gmwm: %l: %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(common.log_level));
  if (common.threads <= 0) return nullptr;
  return std::make_shared<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(common.threads));
}

void declare_output(const CommonOptions& common, const std::string& option, const std::string& path) {
  if (path.empty()) return;
  common.outputs->declare(option, path);
}

void declare_input(const CommonOptions& common, const std::string& path) { common.outputs->add_input(path); }

void commit_outputs(const CommonOptions& common) { common.outputs->commit(); }

void add_report_option(CLI::App& sub, CommonOptions& common) {
  sub.add_option("--report", common.report,
                 "Write a self-contained HTML report with interactive plots to PATH (opens offline), and its main "
                 "plot as PATH.svg")
      ->type_name("PATH");
}

void check_report_option(const CommonOptions& common) {
  if (common.report.empty()) return;
  if (common.report == "-")
    throw InputError("--report '-': expected a file path (the report is a file, with PATH.svg beside it)");
  declare_output(common, "--report", common.report);
  declare_output(common, "--report", report::report_svg_path(common.report));
  if (const std::string why = report::vega_missing_reason(); !why.empty()) throw InputError("--report: " + why);
}

void check_page_report_option(const CommonOptions& common) {
  if (common.report.empty()) return;
  if (common.report == "-") throw InputError("--report '-': expected a file path (the report is a file)");
  declare_output(common, "--report", common.report);
  if (const std::string why = report::vega_missing_reason(); !why.empty()) throw InputError("--report: " + why);
}

void write_report(const CommonOptions& common, const report::ReportData& data) {
  if (common.report.empty()) return;
  report::stage_html_report(*common.outputs, common.report, data);
}

namespace {

io::ReadRequest read_request_of(const InputOptions& input) {
  io::ReadRequest request;
  request.path = input.input;
  if (input.columns) request.columns = io::column_list(*input.columns);
  request.freq = input.freq;
  request.topic = input.topic;
  request.memory_mb = input.memory_mb;
  request.gaps = io::gap_handling_of(input.gaps);
  request.data = io::data_kind_of(input.data);
  request.decimate = input.decimate;
  request.decimate_filter = io::decimation_filter_of(input.decimate_filter);
  return request;
}

void check_levels(const InputOptions& input, const io::SignalSet& set) {
  if (!set.signals.empty())
    if (const std::string why =
            io::levels_problem(input.levels, static_cast<std::int64_t>(set.signals.front().values.size()), "--levels");
        !why.empty())
      throw InputError(input.input + ": " + why);
}

}  // namespace

io::SignalSet read_input(const InputOptions& input) {
  io::SignalSet set = io::read_request(read_request_of(input));
  check_levels(input, set);
  return set;
}

std::vector<io::RecordPart> read_parts(const InputOptions& input) {
  std::vector<io::RecordPart> parts = io::read_request_parts(read_request_of(input));
  for (const io::RecordPart& p : parts) check_levels(input, p.set);
  return parts;
}

namespace {

// A part's line in the merged document's "parts".
report::Json part_entry(const io::RecordPart& part, const report::Json& document) {
  report::Json names = report::Json::array();
  for (const io::Signal& s : part.set.signals) names.push_back(s.name);
  report::Json entry = {{"topic", part.topic.empty() ? report::Json(nullptr) : report::Json(part.topic)},
                        {"stamps", part.stamps.empty() ? report::Json(nullptr) : report::Json(part.stamps)},
                        {"freq", part.set.freq},
                        {"samples", part.set.signals.empty() ? 0 : part.set.signals.front().values.size()},
                        {"columns", std::move(names)}};
  if (document.contains("timing")) entry["timing"] = document.at("timing");
  return entry;
}

std::string part_heading(const io::RecordPart& part) { return part.label() + " (" + fmt(part.set.freq) + " Hz)"; }

}  // namespace

namespace {

using SharedOutcomes = std::shared_ptr<const std::vector<Outcome>>;

// The parts' report pages as one: the first's header, each part's notes after a line naming
// its columns, every part's columns in turn (a part without a page, every fit failed, left out).
std::function<report::ReportData()> merged_report(SharedOutcomes outcomes, std::vector<std::string> headings) {
  if (std::none_of(outcomes->begin(), outcomes->end(), [](const Outcome& o) { return bool(o.report); })) return {};
  return [outcomes, headings] {
    report::ReportData data;
    bool first = true;
    for (std::size_t i = 0; i < outcomes->size(); ++i) {
      if (!(*outcomes)[i].report) continue;
      report::ReportData part = (*outcomes)[i].report();
      if (first) data = part, data.notes.clear(), data.columns.clear(), first = false;
      std::string names;
      for (const report::ReportColumn& c : part.columns) names += (names.empty() ? "" : ", ") + c.name;
      data.notes.push_back(headings[i] + ": columns " + names);
      for (const std::string& note : part.notes)  // a note naming its topic already is said as it is
        data.notes.push_back(note.rfind("topic ", 0) == 0 ? note : headings[i] + ": " + note);
      for (report::ReportColumn& c : part.columns) data.columns.push_back(std::move(c));
    }
    return data;
  };
}

// The parts' tables in turn, each under its heading, each formed from its own document.
std::function<std::string(const report::Json&)> merged_table(SharedOutcomes outcomes,
                                                             std::vector<std::string> headings) {
  return [outcomes, headings](const report::Json& doc) {
    std::string out;
    for (std::size_t i = 0; i < outcomes->size(); ++i) {
      if (!(*outcomes)[i].table) continue;
      report::Json own = (*outcomes)[i].document;
      if (doc.contains("run")) own["run"] = doc.at("run");
      out += (out.empty() ? "" : "\n") + headings[i] + ":\n" + (*outcomes)[i].table(own);
    }
    return out;
  };
}

}  // namespace

Outcome merge_parts(const std::vector<io::RecordPart>& parts, std::vector<Outcome> outcomes) {
  if (outcomes.size() == 1) return std::move(outcomes.front());
  Outcome merged;
  merged.document = outcomes.front().document;
  merged.document.erase("timing");
  report::Json columns = report::Json::array(), entries = report::Json::array();
  std::vector<std::string> headings;
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    for (const report::Json& c : outcomes[i].document.at("columns")) columns.push_back(c);
    entries.push_back(part_entry(parts[i], outcomes[i].document));
    headings.push_back(part_heading(parts[i]));
    for (const auto& [name, seconds] : outcomes[i].seconds)
      merged.seconds[name] = name == "total" ? std::max(merged.seconds[name], seconds) : merged.seconds[name] + seconds;
  }
  merged.document["columns"] = std::move(columns);
  merged.document["parts"] = std::move(entries);
  const auto shared = std::make_shared<const std::vector<Outcome>>(std::move(outcomes));
  merged.report = merged_report(shared, headings);
  merged.table = merged_table(shared, headings);
  return merged;
}

std::string merge_csv_tables(const std::vector<std::string>& tables) {
  std::string out;
  for (const std::string& t : tables) {
    if (out.empty()) {
      out = t;
      continue;
    }
    const auto body = t.find('\n');
    if (body != std::string::npos) out += t.substr(body + 1);
  }
  return out;
}

WvOptions wv_options(const InputOptions& input) {
  WvOptions o;
  o.alpha = input.alpha;
  o.levels = input.levels;
  if (!(input.alpha > 0.0 && input.alpha < 1.0))
    throw InputError("--alpha " + fmt(input.alpha) + ": expected a number in (0, 1)");
  if (input.levels < 0)
    throw InputError("--levels " + std::to_string(input.levels) + ": expected a positive number of levels");
  return o;
}

void check_models_before_reading(const InputOptions& input, const std::vector<ModelSpec>& models) {
  if (!input.freq) return;
  if (const std::string why = io::sampling_rate_problem(*input.freq, "--freq"); !why.empty()) throw InputError(why);
  for (const ModelSpec& m : models) m.bind(ProcessContext{*input.freq, true});
}

int active_threads() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

void write_json(const CommonOptions& common, report::Json& doc, report::RunInfo run) {
  if (common.json.empty()) return;
  run.threads = active_threads();
  run.argv = common.argv;
  report::add_run_info(doc, run);
  common.outputs->stage(common.json, report::dump_json(doc));
}

int emit(const CommonOptions& common, Outcome outcome) {
  write_json(common, outcome.document, {.threads = 0, .seconds = std::move(outcome.seconds), .argv = {}});
  if (!common.report.empty() && outcome.report) write_report(common, outcome.report());
  if (!common.report.empty() && outcome.stage_own_report) outcome.stage_own_report();
  commit_outputs(common);
  if (common.show_table() && outcome.table) print_text(outcome.table(outcome.document));
  return 0;
}

void warn(const std::string& message) { std::cerr << "gmwm: warning: " << printable_line(message) << '\n'; }

void print_text(const std::string& text) { std::cout << report::wrap_to_width(printable_text(text)) << std::flush; }

void warn_about_timing(const io::SignalSet& set) {
  if (const std::string c = io::conditioning_summary(set); !c.empty())
    std::cerr << "gmwm: note: " << printable_line(set.path + ": " + c) << '\n';
  for (const std::string& note : io::reading_notes(set)) warn(set.path + ": " + note);
  if (!set.timing) return;
  const io::TimingReport& t = *set.timing;
  if (t.gaps > 0 && !set.missing.empty()) {
    warn(set.path + ": column '" + t.column + "': " + io::gaps_summary(set));
    // Frequent gaps leave no long window: the long scales (K, B) are not in the estimates.
    if (const std::string note = io::long_scales_note(set); !note.empty()) warn(set.path + ": " + note);
  } else if (t.gaps > 0)
    warn(set.path + ": column '" + t.column + "' has " + std::to_string(t.gaps) +
         " gap(s) in its timestamps (largest " + fmt(t.largest_gap_seconds) + " s), joined end to end" +
         (set.gaps == io::GapHandling::kJoin ? " (--gaps join)"
          : t.rate_change                    ? " (--freq takes the samples as evenly spaced)"
                                             : " (the stamps' jitter, " + fmt(100.0 * t.jitter) +
                                "% of a period between quartiles, cannot tell a lost sample from a "
                                "late stamp)"));
  if (t.disorder > 0)
    warn(set.path + ": column '" + t.column + "' has " + std::to_string(t.disorder) +
         " timestamp(s) out of order: " + t.disorder_text());
  if (t.rate_change)  // read only with --freq: the samples are taken as evenly spaced
    warn(set.path + ": column '" + t.column + "': " + t.rate_change_text() +
         "; --freq takes the samples as evenly spaced");
  if (t.given_freq && t.estimated_freq > 0 &&
      std::abs(*t.given_freq - t.estimated_freq) > io::TimingReport::kDisagreement * t.estimated_freq)
    warn(set.path + ": --freq " + fmt(*t.given_freq) + " Hz disagrees with the " + fmt(t.estimated_freq) +
         " Hz of column '" + t.column + "'; using --freq");
}

ProgressBar::ProgressBar(std::string label, const CommonOptions& common)
    : label_(std::move(label)), enabled_(common.show_table() && isatty(STDERR_FILENO)) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double done, double total) {
  if (!enabled_ || !(total > 0.0)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  const double now = clock_.seconds();
  const bool complete = done >= total;
  if (!complete && last_draw_ >= 0.0 && now - last_draw_ < kRedrawSeconds) return;
  last_draw_ = now;
  const double f = std::clamp(done / total, 0.0, 1.0);
  const int filled = static_cast<int>(std::lround(f * kWidth));
  std::string line = "\r" + label_ + " [" + std::string(static_cast<std::size_t>(filled), '#') +
                     std::string(static_cast<std::size_t>(kWidth - filled), '-') + "] " +
                     std::to_string(static_cast<long long>(done)) + " / " +
                     std::to_string(static_cast<long long>(total)) + " (" +
                     std::to_string(static_cast<int>(std::lround(100.0 * f))) + "%)";
  if (complete)
    line += ", " + fmt(now, 3) + " s";
  else if (f > 0.0)
    line += ", " + fmt(now * (1.0 - f) / f, 2) + " s left";
  line += "    ";
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
  drawn_ = true;
  if (complete) {
    std::fputc('\n', stderr);
    finished_ = true;
  }
}

void ProgressBar::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (drawn_ && !finished_) std::fputc('\n', stderr);
  finished_ = true;
}

// --kalibr FILE[:imuN] (declared in common.h): the file, and the IMU of a chain (empty: the file is one IMU).
// Split at the last ':' only when the whole text is not a file, its head is, and its
// tail names an IMU (a file name may contain ':').
std::pair<std::string, std::string> kalibr_source(const std::string& option, const std::string& text) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || fs::exists(text, ec)) return {text, ""};
  const std::string imu = text.substr(colon + 1);
  const bool names_imu =
      imu.size() > 3 && imu.rfind("imu", 0) == 0 && imu.find_first_not_of("0123456789", 3) == std::string::npos;
  if (names_imu) return {text.substr(0, colon), imu};  // a missing FILE is then reported by its own name
  if (!fs::exists(text.substr(0, colon), ec)) return {text, ""};
  throw InputError(option + " " + text + ": expected FILE or FILE:imuN (e.g. imu_chain.yaml:imu1), got '" + imu + "'");
}

}  // namespace gmwm::cli
