#pragma once
// `gmwm fleet --scheduler ADDRESS`: the recordings as tasks on a Dask distributed cluster,
// through the Python module (python/gmwm/_fleet_dask.py, run as a child process: the tasks'
// texts in on its standard input, one JSON line each, the records out on its standard output
// as they finish). Every worker runs gmwm._gmwm.fleet_task, the same library call a local run
// makes, so the table is the local one.

#include <string>

#include "gmwm/fleet/fleet_study.h"

namespace gmwm::cli {

/// The runner that hands the tasks to the scheduler at `address` ("tcp://host:8786"). The
/// Python interpreter is $GMWM_PYTHON, else the one the module was built for, else python3;
/// the gmwm package is looked for beside
/// this program (the build tree's python/, an installation's lib/pythonX.Y/...) before the
/// interpreter's own path. When the child cannot start or the cluster fails before every
/// task is back, throws InputError with the child's last line (the records back by then
/// are cached: a re-run resumes).
fleet::FleetRunner dask_runner(const std::string& address);

/// Refuses an address that is not "[tcp|tls|inproc|ucx]://HOST[:PORT]" or "HOST:PORT", with
/// the reason (InputError): checked before any work.
void check_scheduler_address(const std::string& address);

}  // namespace gmwm::cli
