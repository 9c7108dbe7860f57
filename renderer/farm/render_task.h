// One render of a batch or farm: `kiln render SCENE ARGS... -o OUTPUT`, and the files that say
// how far it got (OUTPUT.exr, OUTPUT.ckpt from the checkpoint interface, OUTPUT.done from us).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "color/atomic_file.h"

namespace kiln::farm {

// A malformed job file or farm directory: exit 2, one line naming the file.
class FarmInputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct RenderTask {
    std::string scene;              // absolute path
    std::vector<std::string> args;  // render options (camera, size, samples, ...)
    std::string output;             // absolute base: OUTPUT.exr, OUTPUT.png, OUTPUT.ckpt
};

// The `kiln render` command line of a task (without the program), always resumable: --resume
// continues from OUTPUT.ckpt or starts afresh, --checkpoint-every saves progress.
std::vector<std::string> renderCommand(const RenderTask& task, int checkpointSeconds, bool quiet);

// The done marker holds the command line that made the output (less -q), so a changed job renders
// again.
std::string doneMarkerPath(const std::string& output);
bool isComplete(const std::string& output, const std::vector<std::string>& command);
void markComplete(const std::string& output, const std::vector<std::string>& command);
bool hasCheckpoint(const std::string& output);

std::string readFileText(const std::string& path);

}  // namespace kiln::farm
