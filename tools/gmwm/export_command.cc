// gmwm export INPUT --format F --output PATH [--model SPEC] [--aggregate per-axis|mean|worst]
//                   [--inflate X] [--rate HZ] [--units gyro=deg/s,accel=g] [--sensor gyro|accel]
// The fitted noise parameters in the exact form a consumer reads (io/export.h): from a
// `gmwm fit --json` / `gmwm select --json` result, or from a data file fitted first with
// --model (as `gmwm fit` does: classical WV, diagonal Omega).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "common.h"
#include "gmwm/engine/parallel.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/nav_study.h"

namespace gmwm::cli {
namespace {

// A data file whose fit failed: no usable result (exit 1, docs/cli.md), nothing written.
class NoUsableResult : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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
    o.columns = split_list(*a.input.columns);
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
  const WvOptions wv_opts = wv_options(a.input);
  if (a.input.freq) {
    if (const std::string why = io::sampling_rate_problem(*a.input.freq, "--freq"); !why.empty()) throw InputError(why);
    parse_model(a.model, ProcessContext{*a.input.freq, true});
  }
  const auto units = a.units.empty() ? std::map<io::SensorKind, io::Unit>{} : io::parse_declared_units(a.units);
  const auto sensor = sensor_of(a.sensor);
  const io::SignalSet set = read_input(a.input);
  const Model model = parse_model(a.model, ProcessContext{set.freq, set.freq_known});
  std::vector<io::ExportColumn> columns(set.signals.size());
  for (std::size_t k = 0; k < set.signals.size(); ++k) {
    const io::Signal& s = set.signals[k];
    io::ExportColumn& c = columns[k];
    c.name = s.name;
    c.kind = sensor ? *sensor : io::sensor_kind_of_column(s.name);
    c.freq = set.freq;
    c.n = static_cast<std::int64_t>(s.values.size());
    // The unit: --units, else the file's own (EuRoC's header units); never assumed.
    if (const auto given = units.find(c.kind); given != units.end()) {
      c.unit = given->second;
    } else if (!s.unit.empty()) {
      try {
        c.unit = io::parse_unit(s.unit, c.kind);
      } catch (const InputError& e) {
        throw InputError(set.path + ": column '" + s.name + "': its header gives the unit '" + s.unit +
                         "', which is not a " + io::to_string(c.kind) + " unit (" + e.what() + "); give --units");
      }
    } else {
      throw InputError(set.path + ": column '" + s.name + "': the file does not say its unit; give --units " +
                       io::to_string(c.kind) + "=UNIT (" +
                       (c.kind == io::SensorKind::kGyro ? "rad/s, deg/s or deg/h" : "m/s^2, g or mg") + ")");
    }
  }
  const std::vector<WaveletVariance> wvs = compute_wv(set, wv_opts);
  for (const auto& w : wvs) check_model_fits_levels(model, w.levels());
  FitOptions options;
  options.alpha = a.input.alpha;
  options.seed = common.seed;
  options.max_evaluations = a.max_evaluations;
  options.inference = false;          // the export needs the estimates only
  options.omega = OmegaKind::kModel;  // as `gmwm fit` weighs by default
  std::vector<FitResult> fits(wvs.size());
  gmwm::parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t k) { fits[k] = fit_gmwm(wvs[k], model, options); });
  warn_about_timing(set);
  for (std::size_t k = 0; k < fits.size(); ++k) {
    const FitResult& r = fits[k];
    if (r.status == FitStatus::kFailed || r.theta.size() != r.model.num_parameters() || !r.theta.allFinite())
      throw NoUsableResult("column '" + set.signals[k].name + "': the fit of " + a.model + " failed" +
                           (r.message.empty() ? "" : ": " + r.message) + "; nothing written");
    if (r.status == FitStatus::kNotConverged)
      warn("column '" + set.signals[k].name + "': the fit did not converge" +
           (r.message.empty() ? "" : ": " + r.message));
    columns[k].model = r.model;
    columns[k].theta = r.theta;
    // N, K, B against the data's own Allan deviation (noise_figures.h).
    const FigureReport figures = noise_figure_report(set.signals[k].values, set.freq, r.model, r.theta, nullptr);
    columns[k].figures = io::export_figures(figures.chosen);
  }
  source = "data " + set.path + " fitted with " + a.model + " (as gmwm fit: classical WV, Omega diag)";
  return columns;
}

// --consistent-for RATE,HORIZON[,SIGMA]: the setting of pipeline::consistent_inflation.
pipeline::ConsistencyOptions consistency_options(const std::string& text) {
  const std::vector<std::string> parts = split_list(text);
  pipeline::ConsistencyOptions c;
  std::vector<double> v;
  for (const std::string& p : parts)
    if (const auto x = parse_decimal(p); x && *x > 0.0) v.push_back(*x);
  if (v.size() != parts.size() || v.size() < 2 || v.size() > 3)
    throw InputError(
        "--consistent-for '" + text +
        "': expected RATE,HORIZON[,SIGMA]: the filter's update rate in Hz, the longest time on the IMU alone "
        "in s, and optionally an update's error in m (default 0.05), all positive, e.g. 20,60");
  c.update_rate = v[0];
  c.horizon = v[1];
  if (v.size() == 3) c.fix_sigma = v[2];
  if (const std::string why = c.Validate(); !why.empty()) throw InputError("--consistent-for: " + why);
  return c;
}

// The WN + RW figures a file would hold (SI), as the filter model they make, on the axes
// the truth has: per axis for a per-axis export, else the kind's combined figures.
nav::ImuModel written_model(const io::ExportResult& r, const nav::ImuModel& truth) {
  nav::ImuModel m;
  m.label = "the exported WN + RW figures";
  for (const io::KindExport& k : r.kinds) {
    const bool gyro = k.kind == io::SensorKind::kGyro;
    const auto& axes = gyro ? truth.gyro : truth.accel;
    for (std::size_t a = 0; a < 3; ++a) {
      const io::WrittenNoise& w = k.per_axis ? k.axes[a] : k.combined;
      const double f = axes[a].freq;
      const Model model = parse_model(w.random_walk > 0.0 ? "WN+RW" : "WN", ProcessContext{f, true});
      Eigen::VectorXd theta(model.num_parameters());
      theta(0) = w.noise_density * w.noise_density * f;                       // sigma2 = N^2 f
      if (w.random_walk > 0.0) theta(1) = w.random_walk * w.random_walk / f;  // gamma2 = K^2 / f
      (gyro ? m.gyro : m.accel)[a] = nav::SensorModel{model, theta, f, 1.0};
    }
  }
  return m;
}

report::Json written_json(const io::WrittenNoise& w) {
  return {{"noise_density", report::json_number(w.noise_density)},
          {"random_walk", report::json_number(w.random_walk)},
          {"bias_drive", report::json_number(w.bias_drive)},
          {"bias_correlation_time", report::json_number(w.bias_correlation_time)},
          {"bias_from_random_walk", w.bias_from_random_walk}};
}

report::Json result_json(const io::ExportOptions& o, const io::ExportResult& r, const std::string& output,
                         const std::string& source) {
  report::Json doc = report::json_document("export");
  doc["format"] = io::to_string(o.format);
  doc["output"] = output;
  doc["sidecar"] = r.sidecar ? report::Json(output + ".txt") : report::Json(nullptr);
  doc["source"] = source;
  doc["aggregation"] = io::to_string(o.aggregation);
  doc["inflate"] = report::json_number(o.inflate);
  doc["inflate_walk"] = report::json_number(o.inflate_walk.value_or(o.inflate));
  doc["rate"] = report::json_number(r.rate);
  for (const auto& a : r.columns) {
    report::Json c = {{"name", a.column},
                      {"freq", report::json_number(a.freq)},
                      {"kind", io::to_string(a.kind)},
                      {"unit", a.unit.name},
                      {"model", a.model},
                      {"noise_density", report::json_number(a.white)},
                      {"random_walk", report::json_number(a.walk)}};
    report::Json gm = report::Json::array();
    for (const auto& g : a.gauss_markov)
      gm.push_back({{"correlation_time", report::json_number(g.correlation_time)},
                    {"sigma", report::json_number(g.sigma)},
                    {"drive", report::json_number(g.drive)}});
    c["gauss_markov"] = std::move(gm);
    c["others"] = a.others;
    doc["columns"].push_back(std::move(c));
  }
  report::Json kinds = report::Json::object();
  for (const auto& k : r.kinds) {
    if (k.columns.empty()) continue;
    report::Json e = {{"columns", k.columns}, {"per_axis", k.per_axis}, {"combined", written_json(k.combined)}};
    if (k.per_axis)
      e["axes"] = {{"x", written_json(k.axes[0])}, {"y", written_json(k.axes[1])}, {"z", written_json(k.axes[2])}};
    kinds[io::to_string(k.kind)] = std::move(e);
  }
  doc["written"] = std::move(kinds);
  doc["warnings"] = r.warnings;
  return doc;
}

std::string terminal_report(const io::ExportOptions& o, const io::ExportResult& r, const std::string& output) {
  std::ostringstream os;
  os << "wrote " << io::to_string(o.format) << " noise parameters to " << output;
  if (r.sidecar) os << " (header in " << output << ".txt)";
  os << " at " << fmt(r.rate) << " Hz, " << io::to_string(o.aggregation) << ", inflation x" << fmt(o.inflate);
  if (o.inflate_walk && *o.inflate_walk != o.inflate) os << " (random walks x" << fmt(*o.inflate_walk) << ")";
  os << '\n';
  Table t({"sensor", "axis", "noise density", "random walk", "bias drive", "bias T (s)"}, 2);
  for (const auto& k : r.kinds) {
    if (k.columns.empty()) continue;
    const char* si_density = k.kind == io::SensorKind::kGyro ? "rad/s/sqrt(Hz)" : "m/s^2/sqrt(Hz)";
    auto row = [&](const std::string& axis, const io::WrittenNoise& w) {
      t.add({std::string(io::to_string(k.kind)) + " [" + si_density + "]", axis, fmt(w.noise_density, 5),
             fmt(w.random_walk, 5), w.bias_drive > 0 ? fmt(w.bias_drive, 5) : "-",
             w.bias_drive > 0 ? fmt(w.bias_correlation_time, 5) : "-"});
    };
    if (k.per_axis) {
      row("x", k.axes[0]);
      row("y", k.axes[1]);
      row("z", k.axes[2]);
    } else {
      row(io::to_string(o.aggregation), k.combined);
    }
  }
  os << t.str();
  return os.str();
}

int run_export(const ExportArgs& a, const CommonOptions& common) {
  auto threads = apply_common_options(common);
  io::ExportOptions o;
  const auto format = io::parse_export_format(a.format);
  if (!format)
    throw InputError("--format '" + a.format + "': unknown format, expected one of " + io::export_format_names());
  o.format = *format;
  const auto aggregation = io::parse_aggregation(a.aggregate);
  if (!aggregation) throw InputError("--aggregate '" + a.aggregate + "': expected per-axis, mean or worst");
  o.aggregation = *aggregation;
  o.inflate = a.inflate;
  o.rate = a.rate;
  o.rostopic = a.rostopic;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(why);
  if (a.output == "-" && !io::allows_comments(o.format))
    throw InputError("--output -: the " + std::string(io::to_string(o.format)) +
                     " export writes its header to a sidecar PATH.txt; expected a file path");
  declare_input(common, a.input.input);
  declare_output(common, "--output", a.output);
  if (!io::allows_comments(o.format)) declare_output(common, "--output", a.output + ".txt");
  declare_output(common, "--json", common.json);
  if (!a.units.empty()) io::parse_units(a.units);  // a bad --units fails before any work

  std::string source;
  std::vector<io::ExportColumn> columns;
  // Kept open until the data are read: a FIFO's content lives while a reader holds it.
  io::SideFile input(a.input.input, "the --json result of gmwm fit or gmwm select, or a data file");
  try {
    columns = is_json_result(input, a.input.input) ? from_result(a, input, source) : from_data(a, common, source);
  } catch (const NoUsableResult& e) {
    std::cerr << "gmwm: error: " << printable_line(e.what()) << '\n';
    return 1;
  }
  std::optional<pipeline::ConsistentInflation> consistent;
  std::optional<pipeline::ConsistencyOptions> consistency;
  if (!a.consistent_for.empty()) {
    consistency = consistency_options(a.consistent_for);
    if (o.format == io::ExportFormat::kGzSdf || o.format == io::ExportFormat::kRotors)
      throw InputError("--consistent-for: for the WN + RW formats (kalibr, openvins, vins, orbslam3, basalt); " +
                       std::string(io::to_string(o.format)) + " writes the Gauss-Markov bias itself");
    if (a.sub->count("--inflate") > 0) throw InputError("--consistent-for derives the inflation; leave out --inflate");
    pipeline::NavModelInfo truth;
    try {
      truth = pipeline::imu_model_of(columns, a.input.input);
    } catch (const InputError& e) {
      throw InputError(std::string("--consistent-for needs the models of both sensors on every axis (gyroscope and "
                                   "accelerometer columns): ") +
                       e.what());
    }
    const io::ExportResult plain = io::render_export(columns, o, source);
    consistent = pipeline::consistent_inflation(truth.model, written_model(plain, truth.model), *consistency);
    o.inflate = consistent->white;
    o.inflate_walk = consistent->factor;
    o.inflation_reason = consistent->reason;
  }
  const io::ExportResult r = io::render_export(columns, o, source);

  // Everything is computed: write the file (and its sidecar), then the JSON.
  common.outputs->stage(a.output, r.content);
  if (r.sidecar) common.outputs->stage(a.output + ".txt", *r.sidecar);
  for (const auto& w : r.warnings) warn(w);
  report::Json doc = result_json(o, r, a.output, source);
  doc["consistent_for"] = nullptr;
  if (consistent)
    doc["consistent_for"] = {{"update_rate", report::json_number(consistency->update_rate)},
                             {"horizon", report::json_number(consistency->horizon)},
                             {"fix_sigma", report::json_number(consistency->fix_sigma)},
                             {"white_factor", report::json_number(consistent->white)},
                             {"walk_factor", report::json_number(consistent->factor)},
                             {"verdict", nav::to_string(consistent->verdict)},
                             {"nees_inside", report::json_number(consistent->nees_inside)},
                             {"smaller_factor", report::json_number(consistent->smaller)},
                             {"smaller_factor_above_band", report::json_number(consistent->smaller_above)},
                             {"reason", consistent->reason}};
  write_json(common, doc, {.threads = 0, .seconds = {}, .argv = {}});
  commit_outputs(common);
  if (common.show_table() && a.output != "-") {
    print_text(terminal_report(o, r, a.output));
    if (consistent)
      print_text("inflation N x" + fmt(consistent->white, 3) + ", K x" + fmt(consistent->factor, 3) +
                 ": the smallest keeping the filter from being optimistic (" + fmt(consistency->update_rate) +
                 " Hz updates, " + fmt(consistency->horizon) + " s on the IMU alone); NEES in band " +
                 fmt(100.0 * consistent->nees_inside, 3) + "% (" + nav::to_string(consistent->verdict) + ")\n");
  }
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
                  "With a data file INPUT: the model to fit first, e.g. 'WN+RW' (as gmwm fit, Omega diag)")
      ->type_name("SPEC");
  sub->add_option("--aggregate", args->aggregate,
                  "How a sensor's axes become the file's figures: per-axis (basalt, gz-sdf only), mean or worst "
                  "(the largest value of each figure)")
      ->type_name("HOW")
      ->capture_default_str();
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
      ->check(CLI::IsMember({"gyro", "accel"}));
  sub->add_option("--rostopic", args->rostopic, "rostopic for kalibr and openvins")
      ->type_name("TOPIC")
      ->capture_default_str();
  add_max_evaluations_option(*sub, args->max_evaluations);
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_export(*args, common); }};
}

}  // namespace gmwm::cli
