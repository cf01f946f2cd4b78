// gmwm plan (RESULT.json | --model SPEC_WITH_VALUES --freq HZ) [--precision P] [--confidence C]
//           [--targets N,K,B,...] [--have SECONDS] [--columns a,b]
// How long to record (docs/noise-figures.md, "How long to record"): per column, the record
// length at which N, K, B or a parameter reach a relative precision at a confidence. Parses,
// runs pipeline::study_plan, renders with io/plan_output.h, commits.
#include "common.h"
#include "gmwm/io/read_request.h"
#include "gmwm/engine/error.h"
#include "gmwm/report/plan_output.h"
#include "gmwm/pipeline/plan_study.h"

namespace gmwm::cli {
namespace {

struct PlanArgs {
  std::string result, model, targets, columns, unit;
  std::optional<double> freq;
  double precision = 0.1, confidence = 0.95, have = 0.0;
};

int run_plan(const PlanArgs& a, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  declare_output(common, "--json", common.json);
  pipeline::PlanStudyOptions o;
  o.result = a.result;
  o.model = a.model;
  o.freq = a.freq;
  o.unit = a.unit;
  if (!a.columns.empty()) o.columns = io::comma_list(a.columns);
  if (!a.targets.empty()) o.plan.targets = io::comma_list(a.targets);
  o.plan.precision = a.precision;
  o.plan.confidence = a.confidence;
  o.plan.record_seconds = a.have;
  if (!o.result.empty()) declare_input(common, o.result);
  const pipeline::PlanStudy study = pipeline::study_plan(o);
  report::Json doc = report::plan_document(study, o.plan);
  write_json(common, doc, {.threads = active_threads(), .seconds = {{"total", total.seconds()}}, .argv = {}});
  commit_outputs(common);
  if (common.show_table()) print_text(report::plan_terminal(study, o.plan));
  return 0;
}

}  // namespace

Command add_plan_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* sub = app.add_subcommand(
      "plan", "How long to record: the record length at which N, K, B or a parameter reach a precision, per column");
  sub->add_option("RESULT", args->result, "A gmwm fit/select --json result (or give --model and --freq)");
  sub->add_option("--model", args->model, "A model with every value (instead of a result), e.g. a datasheet's")
      ->type_name("SPEC_WITH_VALUES");
  sub->add_option("--freq", args->freq, "The model's sampling rate, Hz")->transform(sampling_rate_number());
  sub->add_option("--unit", args->unit, "The model's unit, for the figures' labels (e.g. deg/s)");
  sub->add_option("--precision", args->precision, "Relative half-width: 0.1 = within +-10%")
      ->transform(decimal_number([](double x) { return x > 0.0 && x < 1.0; }, "a fraction in (0, 1)"))
      ->capture_default_str();
  sub->add_option("--confidence", args->confidence, "The probability of landing within it")
      ->transform(decimal_number([](double x) { return x > 0.0 && x < 1.0; }, "a probability in (0, 1)"))
      ->capture_default_str();
  sub->add_option(
      "--targets", args->targets,
      "N, K, B or parameter labels (WN[1].sigma2, AR1[2].phi), comma-separated (default: N, K, B the model has)");
  sub->add_option("--have", args->have, "Also the precision a record of this many seconds reaches")
      ->type_name("SECONDS")
      ->transform(decimal_number([](double x) { return x > 0.0; }, "a positive duration in seconds"));
  sub->add_option("--columns", args->columns, "The result's columns to plan (default: all)");
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_plan(*args, common); }};
}

}  // namespace gmwm::cli
