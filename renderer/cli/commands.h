// The kiln subcommands; each returns the process exit code (0 ok, 1 failure found, 2 bad
// input/usage).
#pragma once

#include <string>
#include <vector>

namespace kiln {

int runRender(const std::vector<std::string>& args);
int runMerge(const std::vector<std::string>& args);  // kiln merge SHARD.ckpt... -o OUT
int runInfo(const std::vector<std::string>& args);
int runCrosscheck(const std::vector<std::string>& args);
int runBench(const std::vector<std::string>& args);
int runBatch(const std::vector<std::string>& args);            // kiln batch FILE
int runFarm(const std::vector<std::string>& args);             // kiln farm submit|status|...
int runTools(const std::vector<std::string>& args);            // kiln tools subdivide
int runAccuracyCommand(const std::vector<std::string>& args);  // kiln bench accuracy
int runReport(const std::vector<std::string>& args);           // kiln report cs184

}  // namespace kiln
