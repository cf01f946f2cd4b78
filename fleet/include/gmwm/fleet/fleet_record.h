#pragma once
// One recording of a fleet as a unit of work: the task (how to read the recording and the
// study's options, as JSON text that any worker can run) and the record (its result, as JSON
// text with every double written exactly: what the cache keeps and a worker sends back).
// Reading a record back gives the values the computation gave, to the last bit, so a table
// assembled from cached or remote records is the table computed here.
//
//   const std::string task = fleet_task_text(recording, options);   // on the client
//   const std::string record = run_fleet_task(task);                // anywhere gmwm runs
//   const FleetRecord r = parse_fleet_record(record, "cache entry"); // back on the client

#include <functional>
#include <string>
#include <vector>

#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/fleet_manifest.h"

namespace gmwm::fleet {

/// A recording's result without the manifest's labels (unit, model, group, path): its axes'
/// rows (labels empty) and curves, or its failure.
struct FleetRecord {
  std::string status = "ok";  ///< "ok", or why the recording has no result (one line)
  double freq = NAN;
  double seconds = 0.0;             ///< wall time of reading and selecting
  std::vector<FleetRow> axes;       ///< per column, in the recording's order
  std::vector<FleetCurves> curves;  ///< per column
};

/// The version of the record and task texts: a cached record of another version is not read.
/// 2: the WV's partial windows and the Allan deviation's complete and partial ones.
/// 3: the recording's missing samples (FleetCurves::missing).
/// 4: the figures Q and R beside N, K and B (a version-3 record is computed again).
inline constexpr int kFleetRecordVersion = 4;

/// Reads and selects one recording as the study does (read -> select -> one row per axis).
/// Never throws for the recording's own faults (unreadable, too short, a fit that fails):
/// they are the record's status. Throws gmwm::Cancelled when options.select.progress does.
FleetRecord study_fleet_recording(const io::FleetRecording& recording, const FleetStudyOptions& options);

/// The task's text: the recording's path (made absolute: a worker runs elsewhere) and how to read it (topic, columns, units, rate)
/// and every option that shapes the result (model, WV, selection and fit settings), and the
/// memory budget. Throws InputError when the options hold what text cannot carry
/// (FleetStudyOptions::Validate).
std::string fleet_task_text(const io::FleetRecording& recording, const FleetStudyOptions& options);

/// The part of the task's text that decides the result (the task's text without the path
/// and the memory budget, which change how, not what, is computed): with the recording's
/// content hash, the cache key (fleet_cache.h).
std::string fleet_result_key_text(const io::FleetRecording& recording, const FleetStudyOptions& options);

/// Runs a task's text (as a worker does): its record's text. Throws InputError for a text
/// that is not a task of this version. `select_progress`, when given, is the selection's
/// progress callback (a text carries no callback): the cancellation point of a run here.
std::string run_fleet_task(const std::string& task_text,
                           const std::function<void(int, int)>& select_progress = nullptr);

/// The record's text (JSON, every double exact; non-finite ones as "nan", "inf", "-inf").
std::string fleet_record_text(const FleetRecord& record);

/// A record that says only why the recording failed (a runner's task that threw).
std::string failed_record_text(const std::string& why);

/// Reads a record's text. Throws InputError naming `source` for a text that is not a
/// record of this version.
FleetRecord parse_fleet_record(const std::string& text, const std::string& source);

}  // namespace gmwm::fleet
