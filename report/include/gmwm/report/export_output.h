#pragma once
// The export study's renderings (pipeline/export_study.h), shared by the CLI and Python:
// the JSON document `gmwm export --json` writes and the terminal's summary of what was
// written. The file itself is the study's result.content (io/export.h).

#include <string>

#include "gmwm/pipeline/export_study.h"
#include "gmwm/report/json_output.h"

namespace gmwm::report {

/// json_document("export"): format, output (`output` as given), sidecar, source,
/// aggregation, inflation, rate, per column its model and N, K and Gauss-Markov terms,
/// per sensor kind the figures written (combined and per axis), warnings, and
/// "consistent_for" (null without it).
Json export_document(const pipeline::ExportStudy& study, const std::string& output);

/// What was written where, at what rate and inflation, and the figures per sensor and axis
/// (SI units); with consistent_for the factors found and the NEES share in the band.
std::string export_text(const pipeline::ExportStudy& study, const std::string& output);

}  // namespace gmwm::report
