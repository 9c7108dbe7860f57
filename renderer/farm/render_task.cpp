#include "renderer/farm/render_task.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace kiln::farm {

namespace fs = std::filesystem;

std::vector<std::string> renderCommand(const RenderTask& task, int checkpointSeconds, bool quiet) {
    std::vector<std::string> cmd{"render", task.scene};
    cmd.insert(cmd.end(), task.args.begin(), task.args.end());
    cmd.insert(cmd.end(), {"-o", task.output, "--resume", "--checkpoint-every",
                           std::to_string(checkpointSeconds)});
    if (quiet) cmd.push_back("-q");
    return cmd;
}

std::string doneMarkerPath(const std::string& output) { return output + ".done"; }

namespace {
// The command as the done marker holds it: without -q, which changes what a render prints, not
// what it writes (a batch run again with or without -q finds the same outputs complete), nor
// --no-final-checkpoint, which changes what it keeps: a frame a child marked done before a kill
// stays done, whether the batch keeps checkpoints or not.
std::string joinLines(const std::vector<std::string>& command) {
    std::string text;
    for (const std::string& a : command)
        if (a != "-q" && a != "--quiet" && a != "--no-final-checkpoint") text += a + "\n";
    return text;
}
}  // namespace

bool isComplete(const std::string& output, const std::vector<std::string>& command) {
    std::error_code ec;
    if (!fs::exists(output + ".exr", ec) || !fs::exists(doneMarkerPath(output), ec)) return false;
    return readFileText(doneMarkerPath(output)) == joinLines(command);
}

void markComplete(const std::string& output, const std::vector<std::string>& command) {
    writeFileAtomically(doneMarkerPath(output), joinLines(command));
}

bool hasCheckpoint(const std::string& output) {
    std::error_code ec;
    return fs::exists(output + ".ckpt", ec);
}

std::string readFileText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FarmInputError(path + ": cannot be read");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace kiln::farm
