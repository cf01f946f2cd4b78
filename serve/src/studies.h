#pragma once
// What the app's analysis endpoints run: the request body read into the same study options
// the CLI builds from its flags, the study run as a job, and its result rendered by the
// report module (the CLI's JSON document and terminal text, the HTML report's section with
// its Vega specs). Options are read and checked before a job is queued, so that a bad field
// is a 400 at once and a job fails only on what the data say.

#include <memory>
#include <string>

#include "datasets.h"
#include "folder.h"
#include "jobs.h"
#include "request.h"
#include "gmwm/serve/app.h"

namespace gmwm::serve::detail {

/// What the study endpoints share: the options and the open datasets.
struct StudyContext {
  const ServeOptions& options;
  const Folder& folder;
  Datasets& datasets;
};

/// POST /api/wv, /api/fit, /api/select: the job's work (HttpError for a bad request).
Jobs::Work wv_work(const RequestBody& body, StudyContext& context);
Jobs::Work fit_work(const RequestBody& body, StudyContext& context);
Jobs::Work select_work(const RequestBody& body, StudyContext& context);

/// POST /api/stability: the frequency-stability deviations of a column, or with "hat" the
/// three-cornered hat of three ("columns": A, B, C) (`gmwm stability [--hat]`:
/// pipeline::study_stability, its progress and cancellation after each factor), the command's
/// document and text and the report's sections (report::render_stability_fragment).
Jobs::Work stability_work(const RequestBody& body, StudyContext& context);

/// GET /api/stability: what the stability request takes, from the library (the kinds with
/// their titles and the defaults, the tau sets, the interval methods, the noises).
Json stability_choices();

/// GET /api/jobs/ID/ranking/ROW: row ROW (1-based, in ranking order) of a finished
/// selection, as the selection fitted it (its own theta under the selection's shared Omega,
/// no intervals): the model, its criterion and parameters, the report's section for that
/// fit with its noise figures. HttpError 404 for an unknown job or row.
Json ranking_row(const std::shared_ptr<const void>& attachment, const std::string& job, const std::string& row);

/// POST /api/overlay: a simulator's or datasheet's model for a column, its conversions and
/// its WV at the column's scales.
Json overlay(const RequestBody& body, StudyContext& context);

/// POST /api/export: the file `gmwm export RESULT --format F` writes from a fit or select
/// document.
Json export_model(const RequestBody& body);

}  // namespace gmwm::serve::detail
