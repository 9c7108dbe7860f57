// Child processes: kiln's own renders (signals forwarded, so a Slurm TERM reaches the render and
// it checkpoints) and the Slurm client commands (output captured).
#pragma once

#include <string>
#include <vector>

namespace kiln::farm {

// The running kiln binary (/proc/self/exe), so children and farm scripts run this very build.
std::string kilnExecutable();

// Runs program with args, stdio inherited; SIGINT, SIGTERM and SIGUSR1 sent to this process are
// passed on to the child while it runs. Returns its exit code (128 + signal if killed by one).
int runForwardingSignals(const std::string& program, const std::vector<std::string>& args);
// The last signal forwarded by runForwardingSignals (0 if none).
int lastForwardedSignal();

struct CommandResult {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};
// Runs program with args, capturing its output; exit 127 when it cannot be started.
CommandResult runCapturing(const std::string& program, const std::vector<std::string>& args);

}  // namespace kiln::farm
