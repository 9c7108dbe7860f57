// The layering rules of docs/architecture.md as functions over a source root, so that the tests can
// run them on the real tree and on scratch trees with one planted violation each.
//
// Rules (every C++ file is a .h/.hpp/.hh/.cpp/.cc/.cxx under the root, outside hidden folders and
// the top folders the root .gitignore lists as "/NAME/" lines, e.g. /build/ and /build-*/):
// - floors: a C++ file lives in a folder of the floor table (tests/ and below: the roof) and
// includes
//   project headers from its own folder or from folders on lower floors only;
// - quotes: a project header (a path under a top folder of the root, or any file the path names
//   from the root) is included with quotes, never with angle brackets;
// - units: a .h and a .cpp of one stem in one folder are one unit; no two units of one folder
//   include each other, directly or around a longer loop within the folder;
// - Python: the modules under tools/ (tools/**/*.py) do not import each other in a loop.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace kiln::arch {

enum class Rule {
    NoFloorTable,      // docs/architecture.md is missing or has no "| N | `folder` |" rows
    UnlistedFolder,    // a folder holding C++ is not in the floor table
    HigherFloor,       // an include from a folder on a higher floor
    SiblingFolder,     // an include from another folder on the same floor
    UnknownFolder,     // an include from a folder that is not a floor (and not the including one)
    AngleInclude,      // #include <renderer/...>: a project header in angle brackets
    UnitLoop,          // units of one folder include each other
    PythonImportLoop,  // tools/ modules import each other
};
const char* ruleName(Rule rule);

struct Violation {
    Rule rule;
    std::string file;  // relative to the root, '/' separators
    int line = 0;      // 1-based; 0 when the violation is a folder or a loop
    std::string message;
};
// "file:line: [rule] message", one per line.
std::string describe(const std::vector<Violation>& violations);

// folder -> floor from the table in ROOT/docs/architecture.md (empty when there is none).
std::map<std::string, int> readFloors(const std::filesystem::path& root);

// The C++ files under root (relative, sorted) and the Python files under root/tools.
std::vector<std::filesystem::path> cppFiles(const std::filesystem::path& root);
std::vector<std::filesystem::path> toolsPythonFiles(const std::filesystem::path& root);

std::vector<Violation> checkFloors(const std::filesystem::path& root);
std::vector<Violation> checkAngleIncludes(const std::filesystem::path& root);
std::vector<Violation> checkUnitLoops(const std::filesystem::path& root);
std::vector<Violation> checkPythonImports(const std::filesystem::path& root);
// All four.
std::vector<Violation> checkAll(const std::filesystem::path& root);

}  // namespace kiln::arch
