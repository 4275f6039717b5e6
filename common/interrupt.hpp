#pragma once
// Clean interruption: SIGINT and SIGTERM (Ctrl-C, Slurm's scancel, a killed make) remove the temporary
// outputs still being written, say so, and exit with code 3 (ExitCode::kInterrupted). Completed outputs
// were renamed into place and stay.
//
// A signal handler can only reach process-wide state, so this is the one deliberate global of the
// project: a fixed table of temporary paths, touched only through these functions.
#include <filesystem>

#include "common/error.hpp"

namespace nvh {

/// Thrown by a computation that polls interrupt_requested() where it cannot stop with a result (solve's
/// consistent start, before the results file exists; the eccentricities of solve bearing-map): the CLIs
/// exit with code 3 and write nothing.
class Interrupted : public Error {
 public:
  using Error::Error;
};

/// Install the handlers once per process (the tools' main() calls it first).
void install_interrupt_handler(const char* tool);

/// Graceful mode (solve's time loop): a signal only sets a flag that the loop polls with
/// interrupt_requested(), so it can flush its output and write a checkpoint before exiting with code 3.
/// A second signal while the flag is set exits at once, as in the default mode, unless it comes within 2 s of
/// the first (the same request delivered twice, as GNU timeout does: to the child, then to its group).
void set_graceful_interrupt(bool on);
bool interrupt_requested();
/// The signal that set the flag (SIGINT or SIGTERM), 0 if none.
int interrupt_signal();

/// Temporary files to remove on interruption (h5::File registers its temporaries).
void register_temporary(const std::filesystem::path& path);
void unregister_temporary(const std::filesystem::path& path);

}  // namespace nvh
