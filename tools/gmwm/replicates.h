#pragma once
// Replicates on the command line (`--joint FILE[:COLUMN] ...`): further recordings of the
// sensor whose INPUT columns are being fitted. FILE alone adds that file's columns of the
// same names (axis-wise replicates: one joint model per axis); FILE:COLUMN adds one
// column as a replicate of INPUT's single selected column.

#include <string>
#include <vector>

#include "common.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/replicate_study.h"

namespace gmwm::cli {

/// One axis and its replicates, INPUT's column first.
using ReplicateGroup = pipeline::ReplicateGroup;

/// The groups for INPUT's selected columns and the --joint entries (read here, at INPUT's
/// rate). Throws InputError (one line naming the entry) when an entry names a column and
/// INPUT has several selected, a file lacks one of INPUT's columns, a rate differs from
/// INPUT's, or a recording is given twice.
std::vector<ReplicateGroup> read_replicates(const io::SignalSet& input, const std::vector<std::string>& entries,
                                            const InputOptions& options);

/// The file of a --joint entry (FILE[:COLUMN]), for the output safety checks.
std::string replicate_path(const std::string& entry);

}  // namespace gmwm::cli
