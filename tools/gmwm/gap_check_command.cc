// gmwm gap-check [--cases K] [--n N] [--replicates B] [--strengths S1,S2,...]
// The gap diagnosis' withheld-effect self-check (docs/gap.md, method note 5): a confusion matrix, power
// by strength, location and shrinkage per effect family, and the null side.
#include <cmath>
#include <iostream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include "common.h"
#include "gmwm/engine/error.h"
#include "gmwm/gap/gap_check.h"

namespace gmwm::cli {
namespace {

struct GapCheckArgs {
  int cases = 3;
  std::int64_t n = std::int64_t{1} << 18;
  int replicates = 100;
  std::string strengths = "2,4,8";
  std::string families;  ///< empty: every family
  bool no_null = false;
};

int run_gap_check(const GapCheckArgs& args, const CommonOptions& common) {
  Stopwatch total;
  auto threads = apply_common_options(common);
  declare_output(common, "--json", common.json);
  gap::GapCheckOptions o;
  o.cases = args.cases;
  o.n = args.n;
  o.replicates = args.replicates;
  o.strengths = gap::parse_gap_strengths(args.strengths);
  if (!args.families.empty()) o.families = gap::parse_gap_families(args.families);
  o.null_side = !args.no_null;
  o.seed = common.seed;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError("gap-check: " + why);
  ProgressBar bar("gap-check: cases", common);
  if (bar.enabled()) o.progress = [&](int done, int all) { bar.update(done, all); };
  const gap::GapCheckResult r = gap::run_gap_check(o);
  report::Json doc = report::gap_check_document(o, r);
  write_json(common, doc, {.threads = 0, .seconds = {{"total", total.seconds()}}, .argv = {}});
  commit_outputs(common);
  if (common.show_table()) print_text(report::gap_check_text(r));
  return 0;
}

}  // namespace

Command add_gap_check_command(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<GapCheckArgs>();
  CLI::App* sub = app.add_subcommand("gap-check", "The gap diagnosis' self-check on data whose effect was withheld");
  sub->add_option("--cases", args->cases, "Cases per withheld effect (the null side gets 5x and 2x as many)")
      ->transform(whole_number(1, 100000))
      ->capture_default_str();
  sub->add_option("--n", args->n, "Samples per case")
      ->transform(whole_number(256, std::uint64_t{1} << 26))
      ->capture_default_str();
  sub->add_option("--replicates", args->replicates, "Reference replicates per diagnosis")
      ->transform(whole_number(20, 100000))
      ->capture_default_str();
  sub->add_option("--strengths", args->strengths, "Strengths, cycled through each family's cases")
      ->capture_default_str();
  sub->add_option("--families", args->families, "Withheld families, comma-separated (default: all of them)");
  sub->add_flag("--no-null", args->no_null, "Leave out the null side (base-only and off-by-20% cases)");
  add_common_options(*sub, common);
  return {sub, [args, &common] { return run_gap_check(*args, common); }};
}

}  // namespace gmwm::cli
