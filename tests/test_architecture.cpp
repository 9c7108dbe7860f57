// The layering rule of docs/architecture.md, checked on the source tree: every source file lives in
// a folder the table lists, and includes headers only from its own folder or from lower floors.
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// folder -> floor, from the table in docs/architecture.md.
std::map<std::string, int> readFloors() {
    std::ifstream in(test::repo("docs/architecture.md"));
    std::map<std::string, int> floors;
    std::regex row(R"(^\|\s*(\d+)\s*\|\s*`([a-z_/]+)`\s*\|)");
    std::string line;
    std::smatch m;
    while (std::getline(in, line))
        if (std::regex_search(line, m, row)) floors[m[2]] = std::stoi(m[1]);
    return floors;
}

struct Include {
    std::string header;
    int line;
};

std::vector<Include> quotedIncludes(const fs::path& file) {
    std::ifstream in(file);
    std::regex inc(R"re(^\s*#\s*include\s*"([^"]+)")re");
    std::vector<Include> out;
    std::string line;
    std::smatch m;
    for (int n = 1; std::getline(in, line); ++n)
        if (std::regex_search(line, m, inc)) out.push_back({m[1], n});
    return out;
}

std::vector<fs::path> sourceFiles() {
    std::vector<fs::path> files;
    for (const char* top : {"renderer", "scene", "integrators", "color", "python"})
        for (const auto& e : fs::recursive_directory_iterator(test::repo(top))) {
            std::string ext = e.path().extension().string();
            if (e.is_regular_file() && (ext == ".h" || ext == ".cpp")) files.push_back(e.path());
        }
    return files;
}

TEST(Architecture, TheFloorTableIsReadable) {
    auto floors = readFloors();
    EXPECT_GE(floors.size(), 8u);
    EXPECT_EQ(floors.count("renderer/core"), 1u);
    EXPECT_LT(floors["renderer/core"], floors["renderer/cli"]);
}

TEST(Architecture, NoFileIncludesFromAHigherFloorOrASibling) {
    auto floors = readFloors();
    ASSERT_FALSE(floors.empty()) << "docs/architecture.md has no floor table";
    const fs::path root = test::repo("");
    for (const fs::path& file : sourceFiles()) {
        std::string folder = fs::relative(file.parent_path(), root).generic_string();
        auto own = floors.find(folder);
        ASSERT_NE(own, floors.end()) << folder << " holds " << file.filename().string()
                                     << " but is not a floor in docs/architecture.md";
        for (const Include& inc : quotedIncludes(file)) {
            std::string target = fs::path(inc.header).parent_path().generic_string();
            if (target.empty() || target == folder) continue;
            auto theirs = floors.find(target);
            ASSERT_NE(theirs, floors.end()) << file.string() << ":" << inc.line << " includes "
                                            << inc.header << " from a folder that is not a floor";
            EXPECT_LT(theirs->second, own->second)
                << fs::relative(file, root).string() << ":" << inc.line << " (floor " << own->second
                << ", " << folder << ") includes " << inc.header << " (floor " << theirs->second
                << ", " << target << ")";
        }
    }
}

}  // namespace
}  // namespace kiln
