// The layering rules of docs/architecture.md (tests/architecture_check.h), checked on the source
// tree and, one planted violation at a time, on scratch trees: each rule must catch what it
// forbids.
#include <algorithm>
#include <fstream>

#include "architecture_check.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using arch::Rule;
using arch::Violation;

fs::path repoRoot() { return fs::path(test::repo("")).lexically_normal(); }

bool holds(const std::vector<fs::path>& files, const std::string& rel) {
    return std::find(files.begin(), files.end(), fs::path(rel)) != files.end();
}

// ---- the real tree ----

TEST(Architecture, TheFloorTableIsReadable) {
    auto floors = arch::readFloors(repoRoot());
    EXPECT_GE(floors.size(), 8u);
    EXPECT_EQ(floors.count("renderer/core"), 1u);
    EXPECT_LT(floors["renderer/core"], floors["renderer/cli"]);
}

TEST(Architecture, TheScanSeesEveryFolderAndTools) {
    const auto cpp = arch::cppFiles(repoRoot());
    EXPECT_TRUE(holds(cpp, "renderer/core/math.h"));
    EXPECT_TRUE(holds(cpp, "renderer/cli/main.cpp"));
    EXPECT_TRUE(holds(cpp, "integrators/path.h"));
    EXPECT_TRUE(holds(cpp, "tests/test_architecture.cpp"));
    for (const fs::path& f : cpp) {
        const std::string top = f.begin()->string();
        EXPECT_TRUE(top != "build" && top.rfind("build-", 0) != 0) << f << " is a build output";
    }
    const auto py = arch::toolsPythonFiles(repoRoot());
    EXPECT_TRUE(holds(py, "tools/peer_bench.py"));
    EXPECT_TRUE(holds(py, "tools/peer/box.py"));
}

TEST(Architecture, NoFileIncludesFromAHigherFloorOrASibling) {
    const auto v = arch::checkFloors(repoRoot());
    EXPECT_TRUE(v.empty()) << arch::describe(v);
}

TEST(Architecture, ProjectHeadersAreIncludedWithQuotes) {
    const auto v = arch::checkAngleIncludes(repoRoot());
    EXPECT_TRUE(v.empty()) << arch::describe(v);
}

TEST(Architecture, NoTwoUnitsOfAFolderIncludeEachOther) {
    const auto v = arch::checkUnitLoops(repoRoot());
    EXPECT_TRUE(v.empty()) << arch::describe(v);
}

TEST(Architecture, ToolsPythonHasNoImportLoop) {
    const auto v = arch::checkPythonImports(repoRoot());
    EXPECT_TRUE(v.empty()) << arch::describe(v);
}

// ---- scratch trees, one planted violation each ----

void write(const fs::path& root, const std::string& rel, const std::string& text) {
    fs::create_directories((root / rel).parent_path());
    std::ofstream(root / rel) << text;
}

void append(const fs::path& root, const std::string& rel, const std::string& text) {
    std::ofstream(root / rel, std::ios::app) << text;
}

// A small tree that obeys every rule: floors base (0), left and right (1, siblings), top (2); the
// roof; tools/ Python that imports without a loop; a build folder the .gitignore lists.
fs::path cleanTree() {
    const fs::path root = test::scratchDir();
    write(root, "docs/architecture.md",
          "# floors\n\n| floor | folder | holds |\n|---:|---|---|\n"
          "| 0 | `base` | vectors |\n| 1 | `left` | one side |\n| 1 | `right` | the other |\n"
          "| 2 | `top` | the program |\n");
    write(root, ".gitignore", "/build/\n/build-*/\n*.tmp\n");
    write(root, "base/vec.h", "#pragma once\n#include <vector>\n#include <cmath>\n");
    write(root, "base/vec.cpp", "#include \"base/vec.h\"\n#include \"vec.h\"\n");
    write(root, "left/a.h", "#pragma once\n#include \"base/vec.h\"\n");
    write(root, "left/a.cpp", "#include \"left/a.h\"\n#include \"left/c.h\"\n#include <vector>\n");
    write(root, "left/c.h", "#pragma once\n#include <embree3/rtcore.h>\n");
    write(root, "right/b.h", "#pragma once\n#include \"base/vec.h\"\n");
    write(root, "top/app.h", "#pragma once\n#include \"left/a.h\"\n");
    write(root, "top/app.cpp",
          "#include \"top/app.h\"\n#include \"right/b.h\"\n#include <OpenImageIO/imageio.h>\n");
    write(root, "tests/support.h", "#pragma once\n#include \"top/app.h\"\n");
    write(root, "tests/test_app.cpp", "#include \"support.h\"\n#include <gtest/gtest.h>\n");
    // Build outputs break every rule and are not scanned.
    write(root, "build/gen/x.cpp", "#include <top/app.h>\n");
    write(root, "build-sanitize/y.h", "#include \"top/app.h\"\n");
    write(root, "tools/one.py", "import os\nimport two\nfrom three import helper\n");
    write(root, "tools/two.py",
          "\"\"\"Made for one; notes:\n   from one import run\nimport one\n\"\"\"\nimport sys  # "
          "one\n");
    write(root, "tools/sub/three.py", "'''helper'''\nimport json\n\n\ndef helper():\n    pass\n");
    return root;
}

// The violations of one rule.
std::vector<Violation> only(const std::vector<Violation>& all, Rule rule) {
    std::vector<Violation> out;
    for (const auto& v : all)
        if (v.rule == rule) out.push_back(v);
    return out;
}

TEST(ArchitectureCheck, ACleanTreeHasNoViolation) {
    const fs::path root = cleanTree();
    const auto v = arch::checkAll(root);
    EXPECT_TRUE(v.empty()) << arch::describe(v);
    EXPECT_EQ(arch::cppFiles(root).size(), 10u);  // not build/ nor build-sanitize/
    EXPECT_EQ(arch::toolsPythonFiles(root).size(), 3u);
}

TEST(ArchitectureCheck, CatchesAnIncludeFromAHigherFloor) {
    const fs::path root = cleanTree();
    append(root, "base/vec.h", "#include \"top/app.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::HigherFloor);
    EXPECT_EQ(v[0].file, "base/vec.h");
    EXPECT_EQ(v[0].line, 4);
    EXPECT_NE(v[0].message.find("top/app.h (floor 2, top)"), std::string::npos) << v[0].message;
}

TEST(ArchitectureCheck, CatchesAnIncludeFromTheRoof) {
    const fs::path root = cleanTree();
    append(root, "top/app.cpp", "#include \"tests/support.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::HigherFloor);
    EXPECT_EQ(v[0].file, "top/app.cpp");
    EXPECT_EQ(v[0].line, 4);
}

TEST(ArchitectureCheck, CatchesAnIncludeFromASiblingFolder) {
    const fs::path root = cleanTree();
    append(root, "left/a.cpp", "#include \"right/b.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::SiblingFolder);
    EXPECT_EQ(v[0].file, "left/a.cpp");
    EXPECT_EQ(v[0].line, 4);
}

TEST(ArchitectureCheck, CatchesAnAngleBracketProjectInclude) {
    const fs::path root = cleanTree();
    // A lower floor in angle brackets: only the bracket rule is broken.
    append(root, "top/app.cpp", "#include <left/a.h>\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::AngleInclude);
    EXPECT_EQ(v[0].file, "top/app.cpp");
    EXPECT_EQ(v[0].line, 4);
}

TEST(ArchitectureCheck, CatchesTheIssuesExampleOnTheRealFloorTable) {
    // #include <integrators/path.h> from renderer/core passed the old test (it read quotes only).
    const fs::path root = test::scratchDir();
    fs::create_directories(root / "docs");
    fs::copy_file(repoRoot() / "docs/architecture.md", root / "docs/architecture.md");
    write(root, "integrators/path.h", "#pragma once\n#include \"renderer/core/math.h\"\n");
    write(root, "renderer/core/math.h", "#pragma once\n#include <cmath>\n");
    write(root, "renderer/core/bad.h", "#pragma once\n#include <integrators/path.h>\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 2u) << arch::describe(v);
    const auto angle = only(v, Rule::AngleInclude), higher = only(v, Rule::HigherFloor);
    ASSERT_EQ(angle.size(), 1u);
    ASSERT_EQ(higher.size(), 1u);
    EXPECT_EQ(angle[0].file, "renderer/core/bad.h");
    EXPECT_EQ(angle[0].line, 2);
    EXPECT_EQ(higher[0].file, "renderer/core/bad.h");
}

TEST(ArchitectureCheck, CatchesTwoUnitsOfAFolderIncludingEachOther) {
    const fs::path root = cleanTree();
    // left/c.h is included by left/a.cpp; its own .cpp including left/a.h closes the loop.
    write(root, "left/c.cpp", "#include \"left/c.h\"\n#include \"a.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::UnitLoop);
    EXPECT_EQ(v[0].file, "left/a.cpp");
    EXPECT_EQ(v[0].line, 2);
    EXPECT_NE(v[0].message.find("left/c.cpp:2 includes left/a.h"), std::string::npos)
        << v[0].message;
    EXPECT_NE(v[0].message.find("the loop holds left/a left/c"), std::string::npos) << v[0].message;
}

TEST(ArchitectureCheck, CatchesALongerLoopWithinAFolder) {
    const fs::path root = cleanTree();
    // top/app -> top/job -> top/loop -> top/app, through headers and a .cpp.
    append(root, "top/app.h", "#include \"top/job.h\"\n");
    write(root, "top/job.h", "#pragma once\n#include \"top/loop.h\"\n");
    write(root, "top/loop.h", "#pragma once\n");
    write(root, "top/loop.cpp", "#include \"top/loop.h\"\n#include \"top/app.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::UnitLoop);
    EXPECT_NE(v[0].message.find("top/app.h:3 includes top/job.h; top/job.h:2 includes "
                                "top/loop.h; top/loop.cpp:2 includes top/app.h;"),
              std::string::npos)
        << v[0].message;
}

TEST(ArchitectureCheck, CatchesAPythonImportLoop) {
    const fs::path root = cleanTree();
    // A function-local import, as tools/peer_bench.py had: one -> three -> one.
    append(root, "tools/sub/three.py", "\n\ndef late():\n    from one import run  # noqa\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::PythonImportLoop);
    EXPECT_NE(v[0].message.find("tools/one.py:3 imports three; tools/sub/three.py:10 imports one"),
              std::string::npos)
        << v[0].message;
}

TEST(ArchitectureCheck, CatchesAPlainImportLoop) {
    const fs::path root = cleanTree();
    append(root, "tools/two.py", "import json, one as first\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::PythonImportLoop);
    EXPECT_NE(v[0].message.find("tools/two.py:6 imports one"), std::string::npos) << v[0].message;
}

TEST(ArchitectureCheck, CatchesAFolderMissingFromTheTable) {
    const fs::path root = cleanTree();
    // C++ in tools/ must stand on a floor like any other.
    write(root, "tools/fast_bench.cpp", "#include \"base/vec.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::UnlistedFolder);
    EXPECT_EQ(v[0].file, "tools");
    EXPECT_NE(v[0].message.find("fast_bench.cpp"), std::string::npos) << v[0].message;
}

TEST(ArchitectureCheck, CatchesASubfolderMissingFromTheTable) {
    const fs::path root = cleanTree();
    write(root, "left/deep/d.h", "#pragma once\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::UnlistedFolder);
    EXPECT_EQ(v[0].file, "left/deep");
}

TEST(ArchitectureCheck, CatchesAnIncludeFromAFolderThatIsNoFloor) {
    const fs::path root = cleanTree();
    append(root, "top/app.cpp", "#include \"docs/generated.h\"\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::UnknownFolder);
    EXPECT_EQ(v[0].line, 4);
}

TEST(ArchitectureCheck, CatchesAMissingFloorTable) {
    const fs::path root = cleanTree();
    write(root, "docs/architecture.md", "# floors\n\nno table any more\n");
    const auto v = arch::checkAll(root);
    ASSERT_EQ(v.size(), 1u) << arch::describe(v);
    EXPECT_EQ(v[0].rule, Rule::NoFloorTable);
}

}  // namespace
}  // namespace kiln
