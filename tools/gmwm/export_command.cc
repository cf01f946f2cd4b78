// gmwm export INPUT --format F --output PATH [--model SPEC] [--aggregate per-axis|mean|worst]
//                   [--inflate X] [--rate HZ] [--units gyro=deg/s,accel=g] [--sensor gyro|accel]
// The fitted noise parameters in the exact form a consumer reads (io/export.h): from a
// `gmwm fit --json` / `gmwm select --json` result, or from a data file fitted first with
// --model (as `gmwm fit` does by default: classical WV, Omega from the model).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "common.h"
#include "gmwm/io/read_request.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/export_study.h"
#include "gmwm/report/export_output.h"

namespace gmwm::cli {
namespace {

struct ExportArgs {
  InputOptions input;
  std::string format;
  std::string output;
  std::string model;   ///< --model SPEC: fit the data file first
  std::string units;   ///< --units gyro=deg/s,accel=g
  std::string sensor;  ///< --sensor gyro|accel
  std::string aggregate = "mean";
  double inflate = 1.0;
  std::string consistent_for;  ///< --consistent-for RATE,HORIZON[,SIGMA]
  std::optional<double> rate;
  std::string rostopic = "/imu0";
  bool partial = false;  ///< --partial: a sensor with no column is left out, not refused
  int max_evaluations = FitOptions{}.max_evaluations;
  CLI::App* sub = nullptr;  ///< to tell which options were given
};

// Bytes looked at to tell a JSON result from a data file: a byte-order mark and the
// blanks before the first '{' of a JSON document written by any tool fit many times over.
constexpr std::size_t kSniffBytes = 4096;

// A gmwm JSON result starts with '{' (after an optional UTF-8 byte-order mark, which RFC
// 8259 lets a reader ignore, and blanks); data files (text or gzip) never do. The bytes are
// peeked, not consumed: a pipe (`gmwm fit --json - | gmwm export /dev/stdin`) still holds
// them for the JSON or the data reader. A UTF-16 or UTF-32 byte-order mark is named.
bool is_json_result(io::SideFile& input, const std::string& path) {
  const std::string head = input.peek(kSniffBytes);
  std::string_view v(head);
  if (v.starts_with("\xEF\xBB\xBF"))
    v.remove_prefix(3);
  else if (v.starts_with("\xFF\xFE") || v.starts_with("\xFE\xFF") || v.starts_with(std::string_view("\0\0\xFE\xFF", 4)))
    throw InputError(path +
                     ": starts with a UTF-16 or UTF-32 byte-order mark, expected UTF-8 text (the --json "
                     "result of gmwm fit or gmwm select, or a data file)");
  const auto first = v.find_first_not_of(" \t\r\n");
  return first != std::string_view::npos && v[first] == '{';
}

std::optional<io::SensorKind> sensor_of(const std::string& s) {
  if (s.empty()) return std::nullopt;
  return s == "gyro" ? io::SensorKind::kGyro : io::SensorKind::kAccel;
}

// Reads the columns of a fit/select result.
std::vector<io::ExportColumn> from_result(const ExportArgs& a, io::SideFile& input, std::string& source) {
  for (const char* opt : {"--model", "--freq", "--alpha", "--levels", "--max-evaluations"})
    if (a.sub->count(opt) > 0)
      throw InputError(std::string(opt) + ": only for a data file INPUT; '" + a.input.input +
                       "' is a gmwm result whose models are already fitted (--rate sets the update rate)");
  io::ResultReadOptions o;
  if (a.input.columns) {
    o.columns = io::comma_list(*a.input.columns);
    if (o.columns.empty())
      throw InputError("--columns: found an empty list, expected column names separated by commas");
  }
  o.rate = a.rate;
  o.sensor = sensor_of(a.sensor);
  if (!a.units.empty()) o.units = io::parse_declared_units(a.units);
  input.expect("the --json result of gmwm fit or gmwm select");
  io::ResultColumns r = io::read_result_columns(a.input.input, input.read(), o);
  source = "gmwm " + r.command + " result " + a.input.input + (r.input.empty() ? "" : " (data " + r.input + ")");
  for (std::size_t k = 0; k < r.columns.size(); ++k)
    if (r.statuses[k] != "converged")
      warn("column '" + r.columns[k].name + "': its fit's status is " + r.statuses[k] + " in " + a.input.input);
  return std::move(r.columns);
}

// Fits --model to every column of a data file, as `gmwm fit` does.
std::vector<io::ExportColumn> from_data(const ExportArgs& a, const CommonOptions& common, std::string& source) {
  if (a.model.empty())
    throw InputError(a.input.input +
                     ": a data file; give --model SPEC to fit it first, or pass the --json result of "
                     "gmwm fit or gmwm select");
  pipeline::ExportFitOptions o;
  o.model = a.model;
  o.wv = wv_options(a.input);
  o.fit.alpha = a.input.alpha;
  o.fit.seed = common.seed;
  o.fit.max_evaluations = a.max_evaluations;
  if (!a.units.empty()) o.units = io::parse_declared_units(a.units);
  o.sensor = sensor_of(a.sensor);
  check_models_before_reading(a.input, {o.model});
  const io::SignalSet set = read_input(a.input);
  std::vector<std::string> warnings;
  std::vector<io::ExportColumn> columns = pipeline::fitted_export_columns(set, o, warnings);
  warn_about_timing(set);
  for (const std::string& w : warnings) warn(w);
  source = "data " + set.path + " fitted with " + a.model + " (as gmwm fit: classical WV, Omega from the model)";
  return columns;
}

// --consistent-for RATE,HORIZON[,SIGMA]: the setting of pipeline::consistent_inflation.
pipeline::ConsistencyOptions consistency_options(const std::string& text) {
  const std::vector<std::string> parts = io::comma_list(text);
  std::vector<double> v;
  for (const std::string& p : parts)
    if (const auto x = parse_decimal(p)) v.push_back(*x);
  const auto c = v.size() == parts.size() ? pipeline::consistency_from(v) : std::nullopt;
  if (!c)
    throw InputError("--consistent-for '" + text +
                     "': expected RATE,HORIZON[,SIGMA]: " + pipeline::kConsistencyExpected + ", e.g. 20,60");
  if (const std::string why = c->Validate(); !why.empty()) throw InputError("--consistent-for: " + why);
  return *c;
}

// The study's settings (InputError naming the option when invalid).
pipeline::ExportStudyOptions export_options(const ExportArgs& a) {
  pipeline::ExportStudyOptions o;
  const auto format = io::parse_export_format(a.format);
  if (!format)
    throw InputError("--format '" + a.format + "': unknown format, expected one of " + io::export_format_names());
  o.format.format = *format;
  const auto aggregation = io::parse_aggregation(a.aggregate);
  if (!aggregation) throw InputError("--aggregate '" + a.aggregate + "': expected per-axis, mean or worst");
  o.format.aggregation = *aggregation;
  o.format.inflate = a.inflate;
  o.format.rate = a.rate;
  o.format.rostopic = a.rostopic;
  o.format.missing = a.partial ? io::MissingSensor::kLeaveOut : io::MissingSensor::kRefuse;
  if (const std::string why = o.format.Validate(); !why.empty()) throw InputError(why);
  if (a.output == "-" && !io::allows_comments(o.format.format))
    throw InputError("--output -: the " + std::string(io::to_string(o.format.format)) +
                     " export writes its header to a sidecar PATH.txt; expected a file path");
  if (!a.consistent_for.empty()) {
    if (a.sub->count("--inflate") > 0) throw InputError("--consistent-for derives the inflation; leave out --inflate");
    o.consistent_for = consistency_options(a.consistent_for);
  }
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(why);
  return o;
}

int run_export(const ExportArgs& a, const CommonOptions& common) {
  auto threads = apply_common_options(common);
  const pipeline::ExportStudyOptions o = export_options(a);
  declare_input(common, a.input.input);
  declare_output(common, "--output", a.output);
  if (!io::allows_comments(o.format.format)) declare_output(common, "--output", a.output + ".txt");
  declare_output(common, "--json", common.json);
  if (!a.units.empty()) io::parse_units(a.units);  // a bad --units fails before any work

  std::string source;
  std::vector<io::ExportColumn> columns;
  // Kept open until the data are read: a FIFO's content lives while a reader holds it.
  io::SideFile input(a.input.input, "the --json result of gmwm fit or gmwm select, or a data file");
  try {
    columns = is_json_result(input, a.input.input) ? from_result(a, input, source) : from_data(a, common, source);
  } catch (const pipeline::UnusableFit& e) {
    std::cerr << "gmwm: error: " << printable_line(e.what()) << '\n';
    return 1;
  }
  const pipeline::ExportStudy study = pipeline::study_export(columns, source, a.input.input, o);

  // Everything is computed: write the file (and its sidecar), then the JSON.
  common.outputs->stage(a.output, study.result.content);
  if (study.result.sidecar) common.outputs->stage(a.output + ".txt", *study.result.sidecar);
  for (const auto& w : study.result.warnings) warn(w);
  report::Json doc = report::export_document(study, a.output);
  write_json(common, doc, {.threads = 0, .seconds = {}, .argv = {}});
  commit_outputs(common);
  if (common.show_table() && a.output != "-") print_text(report::export_text(study, a.output));
  return 0;
}

}  // namespace

Command add_export_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* sub = app.add_subcommand(
      "export",
      "Write the fitted noise parameters for Kalibr, OpenVINS, VINS, ORB-SLAM3, Basalt, gz-sensors or RotorS, from "
      "a gmwm fit/select --json result or from a data file fitted with --model");
  args->sub = sub;
  add_input_options(*sub, args->input);
  sub->get_option("INPUT")->description(
      "A gmwm fit/select --json result, or a delimited data file (CSV/TSV/..., optionally gzip) to fit with --model");
  sub->add_option("--format", args->format,
                  "Target: kalibr (imu.yaml), openvins (kalibr_imu_chain.yaml), vins (acc_n, gyr_n, acc_w, gyr_w), "
                  "orbslam3 (IMU.NoiseGyro, ...), basalt (calib.json noise fields; JSON has no comments, so the "
                  "header goes to a sidecar PATH.txt), gz-sdf (gz-sensors <sensor>/<imu> <noise> blocks), rotors "
                  "(RotorS/PX4 IMU <plugin> parameters)")
      ->type_name("F")
      ->required();
  sub->add_option("--output", args->output,
                  "The file to write (atomically; basalt also writes PATH.txt with the header)")
      ->type_name("PATH")
      ->required();
  sub->add_option("--model", args->model,
                  "With a data file INPUT: the model to fit first, e.g. 'WN+RW' (as gmwm fit by default: classical WV, "
                  "Omega from the model)")
      ->type_name("SPEC");
  sub->add_option("--aggregate", args->aggregate,
                  "How a sensor's axes become the file's figures: per-axis (basalt, gz-sdf only), mean or worst "
                  "(the largest value of each figure)")
      ->type_name("HOW")
      ->capture_default_str();
  sub->add_flag("--partial", args->partial,
                "Write only the sensors the source has columns of (the other's fields left out, to paste into a file "
                "that has them); without it, a source without gyroscope or accelerometer columns is refused");
  sub->add_option("--inflate", args->inflate,
                  "Multiplies every noise figure written (densities and standard deviations, not variances)")
      ->type_name("X")
      ->transform(decimal_number("a positive factor"))
      ->capture_default_str();
  sub->add_option("--consistent-for", args->consistent_for,
                  "RATE,HORIZON[,SIGMA]: inflate N and K by the smallest factor that keeps a WN + RW filter updated at "
                  "RATE Hz (an update's error SIGMA m, default 0.05) and HORIZON s on the IMU alone from being "
                  "optimistic against the full fitted model (docs/nav.md)")
      ->type_name("RATE,HORIZON");
  sub->add_option_function<double>(
         "--rate", [a = args.get()](const double& r) { a->rate = r; },
         "The IMU rate for update-rate fields and per-sample values (default: the data's rate; needed when a "
         "result has no rate)")
      ->type_name("HZ")
      ->transform(sampling_rate_number());
  sub->add_option("--units", args->units,
                  "Units of the data, e.g. gyro=deg/s,accel=g (default SI, or the result's own); the files are in SI")
      ->type_name("SPEC");
  sub->add_option("--sensor", args->sensor, "Treat every column as this sensor (else told by its name)")
      ->check(choice_of(io::sensor_kind_names()));
  sub->add_option("--rostopic", args->rostopic, "rostopic for kalibr and openvins")
      ->type_name("TOPIC")
      ->capture_default_str();
  add_max_evaluations_option(*sub, args->max_evaluations);
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_export(*args, common); }};
}

}  // namespace gmwm::cli
