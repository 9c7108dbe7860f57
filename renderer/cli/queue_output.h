// What a job queue reads from any kiln command. With --json or --progress json on the command
// line (seen before the command parses it, so a usage error is JSON too) every message on stderr is
// a JSON line; with --json, stdout holds exactly one JSON document, a failure's included, with
// the exit code and its status (docs/output.md, "For a job queue").
#pragma once

#include <string>
#include <vector>

#include "renderer/cli/cli_args.h"
#include "renderer/core/json.h"

namespace kiln {

// Exit codes besides 0 (done), 1 (failure, e.g. a write) and 2 (bad input).
constexpr int kExitTimeLimit = 3;      // --time-limit reached: checkpoint saved, --resume goes on
constexpr int kExitInterrupted = 130;  // SIGINT/SIGTERM: checkpoint (if any) and image saved

struct JsonRequest {
    bool result = false;  // --json: one JSON document on stdout
    bool lines = false;   // --json or --progress json: stderr as JSON lines
};
// Options up to "--" (what follows is a file name).
JsonRequest jsonRequested(const std::vector<std::string>& args);

// "done" (0), "time-limit" (3), "interrupted" (130), "failed" (anything else).
std::string exitStatus(int exitCode);

// One output file and how its write went: kind ("exr", "preview", "heatmap", "checkpoint"), its
// path, and why it was not written (empty: written).
struct OutputWrite {
    std::string kind, path, error;
};
// "outputs" (kind -> path of every file written) and "not_written" ([{kind, path, error}]).
void addOutputs(Json& result, const std::vector<OutputWrite>& writes);

// The document on stdout; a command prints its result through here, so main knows whether a
// failure still needs one.
void printResult(const Json& result);
bool resultPrinted();

// The result of a command that failed before printing its own: command, status, exit_code,
// error, and the outputs it did not write.
Json failureResult(const std::string& command, int exitCode, const std::string& error,
                   const std::vector<OutputWrite>& notWritten);

// A usage error about one output (a directory where the file goes): exit 2, and the result names
// the file as not written.
class OutputError : public UsageError {
  public:
    explicit OutputError(OutputWrite output)
        : UsageError(output.path + ": " + output.error), output_(std::move(output)) {}
    const OutputWrite& output() const { return output_; }

  private:
    OutputWrite output_;
};

}  // namespace kiln
