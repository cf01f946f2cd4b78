#pragma once
// How long to record (docs/noise-figures.md, "How long to record"): for each column of a
// fit/select result, or for one model with values, the record length at which N, K, B (or
// any parameter) reach a relative precision at a confidence level (engine/record_plan.h).
// What `gmwm plan` and Python's gmwm.plan both run.
//
//   gmwm::pipeline::PlanStudyOptions o;
//   o.result = "select.json";               // or o.model = "WN(sigma2=1e-6)+RW(gamma2=1e-12)", o.freq = 100
//   o.plan.precision = 0.1;
//   const gmwm::pipeline::PlanStudy s = gmwm::pipeline::study_plan(o);
//   s.columns[0].plan.targets[0].seconds
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/record_plan.h"
#include "gmwm/io/units.h"

namespace gmwm::pipeline {

struct PlanStudyOptions {
  std::string result;                ///< a fit/select --json result (its columns' models), or
  std::string result_text;           ///< that result's text, when it is not read from the file `result`
                                     ///< (which then only names it; "" when it has no file)
  ModelSpec model;                   ///< a model with every value, at `freq` (checked when assigned)
  std::optional<double> freq;        ///< Hz, for `model` (and results whose "freq" is null)
  std::vector<std::string> columns;  ///< of the result (empty: all)
  std::string unit;                  ///< of `model`, for the figures' labels ("" when unknown)
  RecordPlanOptions plan;
  /// "" when usable, else one line naming the field.
  std::string Validate() const;
};

struct PlanColumn {
  std::string name;
  std::string unit;           ///< the data's unit ("" when unknown)
  std::string model;          ///< with its values, every digit (usable as a model with values)
  std::string display_model;  ///< the same, 4 significant digits (for the terminal)
  RecordPlan plan;
};

struct PlanStudy {
  std::string source;  ///< where the models came from, one line
  std::vector<PlanColumn> columns;
};

/// Throws InputError (one line naming the file, field or target) for anything given wrong.
PlanStudy study_plan(const PlanStudyOptions& options);

}  // namespace gmwm::pipeline
