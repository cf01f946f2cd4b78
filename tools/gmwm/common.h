#pragma once
// Options and helpers shared by the `gmwm` subcommands. The program is thin: it parses
// options, calls the libraries, and decides what goes to the terminal.

#include <chrono>
#include <mutex>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/random.h"
#include "gmwm/report/html_report.h"
#include "gmwm/report/json_output.h"
#include "gmwm/report/report_data.h"
#include "gmwm/report/study_text.h"
#include "gmwm/report/terminal.h"
#include "gmwm/io/output_set.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::cli {

/// Options every command accepts (docs/cli.md).
struct CommonOptions {
  std::string json;  ///< --json PATH ('-' = stdout); empty: none
  int threads = 0;   ///< --threads N; 0: all cores
  std::uint64_t seed = kDefaultSeed;
  bool quiet = false;
  bool verbose = false;  ///< --verbose: the detail tables after the summary
  std::string log_level = "error";
  std::vector<std::string> argv;  ///< the command line, for the JSON "run" object
  std::string report;             ///< --report PATH (wv, fit, select, gap); empty: none
  /// Not an option: the files this run writes, all or none (declared before any work,
  /// staged as results come, committed by commit_outputs()).
  std::shared_ptr<io::OutputSet> outputs = std::make_shared<io::OutputSet>();

  /// True when the terminal table goes to stdout (not --quiet, not --json -).
  bool show_table() const { return !quiet && json != "-"; }
};

/// The largest --levels: J levels need 2^J samples, and no record reaches 2^62.
inline constexpr int kMaxLevelsOption = 62;

/// A decimal number as every option takes it: an optional sign, digits with an optional
/// point and exponent, finite. Not hex floats ("0x1p3"), "inf" or "nan", which strtod (and
/// so CLI11 alone) would take. nullopt otherwise.
std::optional<double> parse_decimal(std::string_view text);

/// The check of a whole-number option, run on its text before CLI11 converts it: plain
/// decimal digits within [lo, hi] ("found '-1', expected an integer from 0 to N"). CLI11
/// alone reads "-1" as 2^64 - 1 into an unsigned option, "010" as 8 and "0x10" as 16; the
/// text is rewritten to its canonical digits so that what is converted is what was checked.
CLI::Validator whole_number(std::uint64_t lo, std::uint64_t hi);

/// The check of a real-number option, run on its text: parse_decimal, then `accept`
/// ("found '0x10', expected <expected>"). The text is rewritten to 17 significant digits.
CLI::Validator decimal_number(std::function<bool(double)> accept, std::string expected);
/// decimal_number accepting any finite value (the command checks its range itself).
CLI::Validator decimal_number(std::string expected);
/// One of an enum's names, listed once beside its parser (gmwm/engine/choice.h): any other
/// text refused as every face refuses it ("found 'x', expected a, b or c").
CLI::Validator choice_of(std::vector<std::string> names);
/// An option of `sub` taking one of `names` into `target`: checked with choice_of, its help
/// `help` followed by the names ("..: static, constant-velocity or manoeuvre"), default shown.
CLI::Option* add_choice(CLI::App& sub, const std::string& name, std::string& target,
                        const std::vector<std::string>& names, const std::string& help);
/// decimal_number within the sampling rates of io::sampling_rate_problem (1e-9 to 1e9 Hz):
/// "found '1e-310', expected a sampling rate in Hz from 1e-09 to 1e+09".
CLI::Validator sampling_rate_number();
/// decimal_number within --memory's range (io::memory_problem: 1 to 1e12 MB), for every
/// command that takes --memory.
CLI::Validator memory_megabytes();

/// INPUT and the options that pick and describe its signals.
struct InputOptions {
  std::string input;
  std::optional<std::string> columns;       ///< --columns a,b,c (names or 1-based indices); given empty: refused
  std::optional<double> freq;               ///< --freq HZ
  std::string topic;                        ///< --topic NAME[:INSTANCE] (PX4 ULog)
  double alpha = 0.05;                      ///< --alpha
  int levels = 0;                           ///< --levels J (0: floor(log2 N))
  std::optional<double> memory_mb;          ///< --memory MB (default: io::kMemoryShare of physical memory)
  std::string gaps = "windows";             ///< --gaps windows|join (io::gap_handling_of)
  std::string data = "rate";                ///< --data rate|increment (io::data_kind_of)
  int decimate = 1;                         ///< --decimate K
  std::string decimate_filter = "average";  ///< --decimate-filter average|none
};

/// --robust, --eff, --estimator, --no-spike-screen.
struct RobustOptions {
  bool robust = false;
  std::optional<double> eff;
  std::optional<std::string> estimator;
  bool no_spike_screen = false;
};

/// A subcommand: its CLI11 node and what to run when it was chosen (returns the exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_wv_command(CLI::App& app, CommonOptions& common);
Command add_fit_command(CLI::App& app, CommonOptions& common);
Command add_simulate_command(CLI::App& app, CommonOptions& common);
Command add_select_command(CLI::App& app, CommonOptions& common);
Command add_gap_command(CLI::App& app, CommonOptions& common);
Command add_gap_check_command(CLI::App& app, CommonOptions& common);
Command add_stability_command(CLI::App& app, CommonOptions& common);

void add_common_options(CLI::App& sub, CommonOptions& common);
void add_input_options(CLI::App& sub, InputOptions& input);
/// add_input_options without --alpha and --levels (a command that reads no WV: stability).
void add_record_options(CLI::App& sub, InputOptions& input);
void add_robust_options(CLI::App& sub, RobustOptions& robust);
/// --max-evaluations N (fit and select).
void add_max_evaluations_option(CLI::App& sub, int& max_evaluations);
/// --first-level L|auto (fit, select: the first level fitted; gap: the first level
/// compared), checked by pipeline::parse_first_level; `first_level` keeps what was given
/// (its default shown). `what` is the help's opening ("Fit the WV from this level on").
void add_first_level_option(CLI::App& sub, std::string& first_level, const std::string& what);
/// --first-level (the first level fitted, "1" by default) and --max-evaluations.
void add_fitting_options(CLI::App& sub, std::string& first_level, int& max_evaluations);
/// The level (or pipeline::kAutoFirstLevel) of a --first-level the option checked.
int first_level_of(const std::string& text);

/// The robust WV settings, or nullopt without --robust. Throws InputError (exit 2) for
/// --eff outside (0, 1), an unknown --estimator, or any of them without --robust.
std::optional<robust::RobustWvOptions> robust_wv_options(const RobustOptions& robust, const WvOptions& wv);

/// Sets up logging (spdlog level, stderr) and returns the TBB parallelism limit to keep
/// alive for the command's duration (nullptr when --threads was not given).
std::shared_ptr<void> apply_common_options(const CommonOptions& common);

/// Declares an output (nothing when `path` is empty) before any work, so that a typo, a
/// device, a symlink, an input or a second output of the same name costs nothing and
/// nothing is written (io::OutputSet::declare; InputError naming the option).
void declare_output(const CommonOptions& common, const std::string& option, const std::string& path);
/// Declares a file the run reads (an output may not be it).
void declare_input(const CommonOptions& common, const std::string& path);
/// Writes every staged output (standard output first, then the files), all or none.
/// Call it once every result is staged, before the terminal table.
void commit_outputs(const CommonOptions& common);

/// --report PATH: the self-contained HTML report (io/html_report.h), plus PATH.svg.
void add_report_option(CLI::App& sub, CommonOptions& common);
/// Checked before any work (InputError, exit 2): --report names a file in an existing
/// folder (not '-') and the Vega modules the page inlines can be read.
void check_report_option(const CommonOptions& common);
/// The same for a report that is one page without PATH.svg (nav, stability).
void check_page_report_option(const CommonOptions& common);
/// Stages the report and its SVG when --report was given.
void write_report(const CommonOptions& common, const report::ReportData& data);

/// Reads INPUT with --columns/--freq; throws InputError when the rate is unknown, and for a
/// --topic list (io::read_request; the commands that read several topics call read_parts).
io::SignalSet read_input(const InputOptions& input);

/// WvOptions from --levels/--alpha (InputError naming the option when invalid).
WvOptions wv_options(const InputOptions& input);

/// With --freq, every model is bound at that rate before INPUT is read, so that a bad value
/// in a long file's command costs nothing (InputError; the text itself was checked when the
/// ModelSpec was made; without --freq the values wait for the file's rate).
void check_models_before_reading(const InputOptions& input, const std::vector<ModelSpec>& models);

/// TBB's current parallelism limit.
int active_threads();

/// Fills RunInfo and stages the JSON document when --json was given.
void write_json(const CommonOptions& common, report::Json& doc, report::RunInfo run);

/// A number for tables: %.6g, "-" when not finite (report/terminal.h).
using report::fmt;

/// A plain text table: columns right-aligned except the first `left` ones.
/// The terminal's tables (report/terminal.h): they fit report::kTerminalWidth columns.
using Table = report::TextTable;

/// Wall-clock seconds since construction.
class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// A progress bar on one line of stderr for long work (gap, gap-check, select, bootstrap):
/// "gap [#########---------] 120 / 400 (30%), 12 s left". Drawn only when the table is
/// shown (not --quiet, not --json -) and stderr is a terminal; redrawn at most every
/// kRedrawSeconds; thread-safe (TBB workers report). The time left extrapolates the
/// elapsed time over the fraction done.
class ProgressBar {
 public:
  ProgressBar(std::string label, const CommonOptions& common);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  bool enabled() const { return enabled_; }
  /// Work done out of total (any units); the last call with done == total ends the line.
  void update(double done, double total);
  /// Ends the line (once) when anything was drawn.
  void finish();

 private:
  static constexpr double kRedrawSeconds = 0.1;
  static constexpr int kWidth = 24;
  std::string label_;
  bool enabled_ = false;
  bool drawn_ = false, finished_ = false;
  double last_draw_ = -1.0;
  Stopwatch clock_;
  std::mutex mutex_;
};

/// Warns on stderr about gaps, disorder, and a --freq that disagrees with the timestamps.
void warn_about_timing(const io::SignalSet& set);

/// Prints "gmwm: warning: <message>" on stderr, as one printable line.
void warn(const std::string& message);

/// What a command has made, for its last stage (emit): the document and its named timings,
/// its HTML report's data (called only with --report; empty: the command writes none), its
/// terminal table (formed from the document with its "run", only when shown) and, for a
/// command whose page is its own (fleet, nav), the staging of that page instead of `report`.
struct Outcome {
  report::Json document;
  std::map<std::string, double> seconds;
  std::function<report::ReportData()> report;
  std::function<std::string(const report::Json&)> table;
  std::function<void()> stage_own_report = {};
};

/// INPUT's parts (io::read_request_parts): one per topic of --topic A,B, each at its own
/// rate, else the one record; each checked as read_input checks the record.
std::vector<io::RecordPart> read_parts(const InputOptions& input);

/// One run of several parts (wv, fit, select over --topic A,B): the first part's document
/// with every part's columns (each carries its own n and freq) and, for the record's
/// "timing", "parts" ([{topic, stamps, freq, samples, columns, timing}]); the timings summed ("total"
/// the run's); the report's columns in turn, each part's notes after a line naming it; the
/// tables in turn under "topic T (F Hz):". One part: its Outcome unchanged.
Outcome merge_parts(const std::vector<io::RecordPart>& parts, std::vector<Outcome> outcomes);

/// A CSV table of every part (--csv, --adev-csv): the first's header once, then each part's rows.
std::string merge_csv_tables(const std::vector<std::string>& tables);

/// Every command's last stage: stages the JSON (write_json) and the report, writes every
/// staged output, all or none (commit_outputs), then prints the table. Returns 0.
int emit(const CommonOptions& common, Outcome outcome);

/// Prints a terminal report on stdout with every control byte but line breaks and tabs
/// shown as \xNN (printable_text): names from files reach the terminal as text, never as
/// escape sequences.
void print_text(const std::string& text);

/// A Kalibr file option's FILE[:imuN]: the file, and the IMU of a chain (empty: the file is
/// one IMU). Split at the last ':' only when the whole text is not a file, its head is, and
/// its tail names an IMU; InputError naming `option` for a tail that names none.
std::pair<std::string, std::string> kalibr_source(const std::string& option, const std::string& text);

}  // namespace gmwm::cli
