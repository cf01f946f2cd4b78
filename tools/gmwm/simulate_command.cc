// gmwm simulate --model SPEC_WITH_VALUES --n N [--freq HZ] [--signals K] [--names a,b]
//               --output PATH
// Simulates K independent series of a fully specified model into a delimited file
// (gzip-compressed when PATH ends in .gz), reproducible from --seed.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "common.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/signal_writer.h"

namespace gmwm::cli {

namespace {

struct SimulateArgs {
  std::string model;
  std::int64_t n = 0;
  std::optional<double> freq;
  int signals = 1;
  std::string names;
  std::string output;
  std::optional<double> quantum;
};

// The simulated series are held in memory (8 bytes a sample and signal) while they are
// written; a request beyond the memory budget (io::kMemoryShare of the physical memory, the
// reader's budget) is refused before anything is allocated, instead of ending in an
// allocation failure.
void check_memory(const SimulateArgs& args) {
  const double limit = io::memory_budget_bytes();
  if (!(limit > 0.0)) return;  // unknown: let the allocation decide
  const double needed = 8.0 * static_cast<double>(args.n) * args.signals;
  if (needed > limit)
    throw InputError("--n " + std::to_string(args.n) + " x " + std::to_string(args.signals) + " signal(s): needs " +
                     fmt(needed / 1e9, 3) + " GB for the samples, more than " + fmt(100.0 * io::kMemoryShare, 3) +
                     "% of this machine's " + fmt(limit / io::kMemoryShare / 1e9, 3) +
                     " GB; expected a smaller --n (or fewer --signals)");
}

std::vector<std::string> column_names(const SimulateArgs& args) {
  std::vector<std::string> names;
  if (args.names.empty()) {
    for (int k = 0; k < args.signals; ++k) names.push_back(args.signals == 1 ? "x" : "x" + std::to_string(k + 1));
    return names;
  }
  std::istringstream is(args.names);
  std::string name;
  while (std::getline(is, name, ',')) names.push_back(name);
  if (static_cast<int>(names.size()) != args.signals)
    throw InputError("--names '" + args.names + "': found " + std::to_string(names.size()) + " names, expected " +
                     std::to_string(args.signals) + " (one per signal, comma-separated)");
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& nm = names[k];
    const bool plain = !nm.empty() && std::all_of(nm.begin(), nm.end(),
                                                  [](char c) { return c > ' ' && c < 0x7f && c != '"' && c != '\''; });
    if (!plain)
      throw InputError("--names: name " + std::to_string(k + 1) +
                       " is empty or has a space, quote or control character, expected plain column names");
    if (io::is_timestamp_column_name(nm))
      throw InputError("--names: '" + nm +
                       "' is a timestamp column's name (gmwm would read it back as "
                       "times, not as a signal), expected another name");
    for (std::size_t j = 0; j < k; ++j)
      if (names[j] == nm) throw InputError("--names: '" + nm + "' is given twice, expected distinct names");
  }
  return names;
}

/// Rounds to multiples of q (a normal double). When 1/q is an integer (q = 1e-6, 0.05, ...)
/// the result is k / (1/q), the double nearest to the decimal k q, so that files show short
/// numbers. A value whose quotient by q reaches 2^53 is kept: q is then below its spacing
/// ulp(v) > |v| 2^-53, so the nearest multiple of q rounds to v itself (dividing 1e300 by
/// q = 1e-10 overflowed to inf, and an inf row was written).
void quantize(std::vector<double>& values, double q) {
  constexpr double kIntegral = 9007199254740992.0;  // 2^53: every double from here on is an integer
  const double inv = std::round(1.0 / q);
  if (inv >= 1.0 && std::abs(inv * q - 1.0) < 1e-12) {
    for (double& v : values)
      if (std::abs(v * inv) < kIntegral) v = std::nearbyint(v * inv) / inv;
  } else {
    for (double& v : values)
      if (std::abs(v / q) < kIntegral) v = std::nearbyint(v / q) * q;
  }
}

/// The first sample of `values` a double does not hold, or -1.
std::int64_t first_non_finite(const std::vector<double>& values) {
  const auto it = std::find_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); });
  return it == values.end() ? -1 : static_cast<std::int64_t>(it - values.begin());
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& nm : names) s += (s.empty() ? "" : ",") + nm;
  return s;
}

// The arguments' own checks, before anything is simulated.
void check_arguments(const SimulateArgs& args) {
  if (args.freq)
    if (const std::string why = io::sampling_rate_problem(*args.freq, "--freq"); !why.empty()) throw InputError(why);
  if (args.quantum && !(*args.quantum > 0.0 && std::isfinite(*args.quantum)))
    throw InputError("--quantum " + fmt(*args.quantum) + ": expected a positive step");
  // A subnormal step divides ordinary values to inf (1 / 1e-320 overflows) and carries
  // fewer than 15 digits of its own.
  if (args.quantum && *args.quantum < std::numeric_limits<double>::min())
    throw InputError("--quantum " + fmt(*args.quantum) +
                     ": expected a step of at least 2.2e-308 (the smallest normal double)");
}

// The model, with a value for every parameter that its processes accept.
Model fully_specified_model(const SimulateArgs& args) {
  const ProcessContext context{args.freq.value_or(1.0), args.freq.has_value()};
  const Model model = parse_model(args.model, context);
  if (!model.fully_specified()) {
    std::string missing;
    const Eigen::VectorXd given = model.given_values();
    for (int k = 0; k < model.num_parameters(); ++k)
      if (std::isnan(given(k))) missing += (missing.empty() ? "" : ", ") + model.parameter_label(k);
    throw InputError("--model '" + args.model + "': found no value for " + missing +
                     ", expected a value for every parameter, e.g. "
                     "'AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=0.01)'");
  }
  if (const std::string why = model.validate(model.given_values()); !why.empty())
    throw InputError("--model '" + args.model + "': " + why);
  return model;
}

// The study: every signal of the model at the seed (InputError when a value leaves the doubles).
std::vector<std::vector<double>> simulated_series(const SimulateArgs& args, const Model& model, std::uint64_t seed) {
  try {
    return simulate_many(model, model.given_values(), args.n, args.signals, seed);
  } catch (const InputError& e) {  // a value beyond a double (simulate.h): nothing is written
    throw InputError("--model '" + args.model + "' with --n " + std::to_string(args.n) + ": " + e.what() +
                     "; expected values a double holds over --n samples (a drift's |omega| (n - 1) <= 1.8e308)");
  }
}

// The signals as written: named, rounded to --quantum (InputError past the largest double).
std::vector<io::Signal> named_signals(const SimulateArgs& args, std::vector<std::vector<double>> series,
                                      const std::vector<std::string>& names) {
  std::vector<io::Signal> signals(series.size());
  for (std::size_t k = 0; k < series.size(); ++k) {
    signals[k].name = names[k];
    if (args.quantum) {
      quantize(series[k], *args.quantum);
      // Rounding up to a multiple past 1.8e308 (a step near the largest double).
      if (const std::int64_t at = first_non_finite(series[k]); at >= 0)
        throw InputError("--quantum " + fmt(*args.quantum) + ": rounding signal '" + names[k] +
                         "' to its multiples takes sample " + std::to_string(at) +
                         " beyond the largest double (1.8e308); expected a smaller step");
    }
    signals[k].values = std::move(series[k]);
  }
  return signals;
}

// Render: the document and the terminal's lines.
report::Json simulate_document(const SimulateArgs& args, const Model& model, const std::vector<io::Signal>& signals,
                               std::uint64_t seed) {
  report::Json doc = report::json_document("simulate");
  doc["model"] = model.to_string(model.given_values());
  doc["seed"] = seed;
  doc["output"] = args.output;
  doc["quantum"] = args.quantum ? report::json_number(*args.quantum) : report::Json(nullptr);
  for (const io::Signal& s : signals)
    doc["columns"].push_back(report::column_json({s.name, args.n, args.freq.value_or(0.0), args.freq.has_value(), {}}));
  return doc;
}

std::string simulate_text(const SimulateArgs& args, const Model& model, const std::vector<std::string>& names,
                          std::uint64_t seed) {
  std::ostringstream os;
  os << "wrote " << args.output << ": " << names.size() << " signal(s) (" << joined(names) << ") x " << args.n
     << " samples" << (args.freq ? " at " + fmt(*args.freq) + " Hz with a timestamp column" : "")
     << (args.quantum ? ", rounded to multiples of " + fmt(*args.quantum) : "")
     << "\nmodel: " << model.to_string(model.given_values()) << "\nseed: " << seed << '\n';
  return os.str();
}

int run_simulate(const SimulateArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  declare_output(common, "--output", args.output);
  declare_output(common, "--json", common.json);
  check_arguments(args);
  const std::vector<std::string> names = column_names(args);
  const Model model = fully_specified_model(args);

  check_memory(args);
  Stopwatch sim_clock;
  const std::vector<io::Signal> signals = named_signals(args, simulated_series(args, model, common.seed), names);
  const double sim_seconds = sim_clock.seconds();

  report::Json doc = simulate_document(args, model, signals, common.seed);
  Stopwatch write_clock;
  io::stage_signals(*common.outputs, args.output, signals, args.freq);
  const double write_seconds = write_clock.seconds();
  return emit(common, {std::move(doc),
                       {{"simulate", sim_seconds}, {"write", write_seconds}, {"total", total.seconds()}},
                       nullptr,
                       [&](const report::Json&) { return simulate_text(args, model, names, common.seed); }});
}

}  // namespace

Command add_simulate_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub = app.add_subcommand("simulate", "Simulate independent series of a fully specified model into a file");
  sub->add_option("--model", args->model, "Model with every value, e.g. 'AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=0.01)'")
      ->type_name("SPEC_WITH_VALUES")
      ->required();
  sub->add_option("--n", args->n, "Samples per signal")
      ->type_name("N")
      ->required()
      ->transform(whole_number(1, std::uint64_t{1} << 40));
  sub->add_option_function<double>(
         "--freq", [args](const double& f) { args->freq = f; },
         "Sampling rate in Hz: adds a timestamp column (seconds)")
      ->type_name("HZ")
      ->transform(sampling_rate_number());
  sub->add_option("--signals", args->signals, "Number of independent signals (columns)")
      ->type_name("K")
      ->transform(whole_number(1, 100000))
      ->capture_default_str();
  sub->add_option("--names", args->names, "Column names, comma-separated (default x, or x1..xK)")->type_name("A,B,C");
  sub->add_option_function<double>(
         "--quantum", [args](const double& q) { args->quantum = q; },
         "Round every value to a multiple of Q, like an ADC's least significant bit (adds "
         "about Q^2/12 of white noise; keeps files small)")
      ->type_name("Q")
      ->transform(decimal_number("a positive step"));
  sub->add_option("--output,-o", args->output, "Output file (CSV; gzip-compressed when PATH ends in .gz)")
      ->type_name("PATH")
      ->required();
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_simulate(*args, common); }};
}

}  // namespace gmwm::cli
