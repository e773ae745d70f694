// Interrupted runs: SIGINT, SIGTERM and SIGHUP remove the temporary file of any write in
// progress (rtd::removeTemporaryFiles) before the process ends with the signal, so neither a
// truncated frame nor a stray `*.tmp<pid>` is left beside the outputs. Files that a run killed
// by SIGKILL left are removed at the next start (rtd::removeStaleTemporaryFiles).
#pragma once

namespace rtd::cli {

/// Installs the handlers (once, at start-up).
void installInterruptHandlers();

}  // namespace rtd::cli
