#include "renderer/cli/queue_output.h"

#include <cstdio>

namespace kiln {
namespace {

bool gResultPrinted = false;

}  // namespace

JsonRequest jsonRequested(const std::vector<std::string>& args) {
    JsonRequest r;
    for (size_t i = 0; i < args.size() && args[i] != "--"; ++i) {
        const std::string& a = args[i];
        const bool progressJson =
            a == "--progress=json" ||
            (a == "--progress" && i + 1 < args.size() && args[i + 1] == "json");
        r.result = r.result || a == "--json";
        r.lines = r.lines || a == "--json" || progressJson;
    }
    return r;
}

std::string exitStatus(int exitCode) {
    switch (exitCode) {
        case 0:
            return "done";
        case kExitTimeLimit:
            return "time-limit";
        case kExitInterrupted:
            return "interrupted";
        default:
            return "failed";
    }
}

void addOutputs(Json& result, const std::vector<OutputWrite>& writes) {
    Json written = Json::object(), failed = Json::array();
    for (const OutputWrite& w : writes) {
        if (w.error.empty())
            written[w.kind] = w.path;
        else
            failed.push_back({{"kind", w.kind}, {"path", w.path}, {"error", w.error}});
    }
    result["outputs"] = written;
    result["not_written"] = failed;
}

void printResult(const Json& result) {
    std::fputs((jsonText(result) + "\n").c_str(), stdout);
    std::fflush(stdout);
    gResultPrinted = true;
}

bool resultPrinted() { return gResultPrinted; }

Json failureResult(const std::string& command, int exitCode, const std::string& error,
                   const std::vector<OutputWrite>& notWritten) {
    Json result = {{"command", command},
                   {"status", exitStatus(exitCode)},
                   {"exit_code", exitCode},
                   {"error", error}};
    addOutputs(result, notWritten);
    return result;
}

}  // namespace kiln
