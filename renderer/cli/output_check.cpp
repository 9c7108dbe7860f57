#include "renderer/cli/output_check.h"

#include <filesystem>
#include <stdexcept>

#include "color/atomic_file.h"
#include "renderer/cli/cli_args.h"

namespace kiln {

namespace fs = std::filesystem;

void checkOutputBase(const std::string& base) {
    const std::string name = fs::path(base).filename().string();
    if (name.empty() || name == "." || name == "..")
        throw UsageError("-o '" + base + "' names a directory, not an output name (e.g. '" +
                         (fs::path(base) / "frame").string() + "')");
    std::error_code ec;
    const fs::path dir = fs::path(base).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw UsageError("output directory '" + dir.string() + "' does not exist");
}

void checkOutputFiles(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
        std::error_code ec;
        if (fs::is_directory(path, ec)) throw UsageError(path + ": is a directory");
        try {
            AtomicFile probe(path);  // removed unwritten when it goes
        } catch (const std::runtime_error& e) {
            throw UsageError(e.what());
        }
    }
}

}  // namespace kiln
