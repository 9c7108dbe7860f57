// Every JSON kiln prints parses with a real parser (nlohmann-json), also for file names with
// quotes, backslashes and bytes that are not UTF-8; the SVG plots parse as XML.
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <sstream>

#include "kiln_run.h"
#include "renderer/validation/svg_plot.h"
#include "test_support.h"

namespace kiln {
namespace {

// A copy of the Cornell box under a name that broke the hand-written JSON.
std::filesystem::path hostileScene(const std::filesystem::path& dir) {
    std::string name = "q\"uo\\te'd \xff\xfe name.dae";
    std::filesystem::path path = dir / name;
    std::filesystem::copy_file(test::repo("scenes/cornell.dae"), path);
    return path;
}

TEST(Json, InfoParsesWithAHostileFileName) {
    auto dir = test::scratchDir();
    auto scene = hostileScene(dir);
    test::CliRun r = test::runKiln("info --json " + test::shellQuoted(scene.string()));
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    std::string name = j["scene"];
    EXPECT_NE(name.find("q\"uo\\te'd "), std::string::npos) << name;
    EXPECT_NE(name.find("\xef\xbf\xbd"), std::string::npos) << name;  // U+FFFD for the bad bytes
    EXPECT_EQ(j["triangles"], 24);
    EXPECT_EQ(j["camera"]["position"].size(), 3u);
    EXPECT_TRUE(j["warnings"].is_array());
}

TEST(Json, CrosscheckParsesWithAHostileFileName) {
    auto dir = test::scratchDir();
    auto scene = hostileScene(dir);
    test::CliRun r =
        test::runKiln("crosscheck --json --rays 400 " + test::shellQuoted(scene.string()));
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["genuine"], 0);
    ASSERT_EQ(j["categories"].size(), 4u);
    for (const auto& c : j["categories"]) EXPECT_EQ(c["rays"], 100) << c.dump();
}

TEST(Json, RenderPrintsOneResultAndProgressLines) {
    auto dir = test::scratchDir();
    auto scene = hostileScene(dir);
    std::string out = (dir / "out \"x\"").string();
    test::CliRun r =
        test::runKiln("render " + test::shellQuoted(scene.string()) +
                      " -r 32 24 -s 4 --json --progress json -o " + test::shellQuoted(out));
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);  // the whole of stdout: one document
    EXPECT_EQ(j["outputs"]["exr"], out + ".exr");
    EXPECT_TRUE(std::filesystem::exists(j["outputs"]["exr"].get<std::string>()));
    EXPECT_TRUE(std::filesystem::exists(j["outputs"]["preview"].get<std::string>()));
    EXPECT_EQ(j["samples"], 32 * 24 * 4);
    EXPECT_EQ(j["spp"], 4.0);
    EXPECT_GT(j["rays"].get<uint64_t>(), uint64_t(32 * 24 * 4));
    EXPECT_GT(j["peak_memory_bytes"].get<uint64_t>(), uint64_t(1) << 20);
    EXPECT_GE(j["seconds"]["render"].get<double>(), 0.0);
    EXPECT_EQ(j["interrupted"], false);
    EXPECT_TRUE(j["warnings"].is_array());
    // Progress: JSON lines on stderr (the messages too), the last progress one "done" at 1.
    std::istringstream err(r.err);
    std::string line;
    nlohmann::json last;
    int lines = 0;
    while (std::getline(err, line)) {
        nlohmann::json j = nlohmann::json::parse(line);  // with --json every line is JSON
        if (j["event"] == "progress" || j["event"] == "done") last = j, ++lines;  // not log, stage
    }
    ASSERT_GE(lines, 1) << r.err;
    EXPECT_EQ(last["event"], "done");
    EXPECT_EQ(last["fraction"], 1.0);
    EXPECT_EQ(last["work_done"], 32 * 24 * 4);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

TEST(JobQueue, UnwritableOutputDirectoryIsRefusedBeforeTheSceneLoads) {
    // /proc exists but takes no new files, even from root; the scene does not exist either, and
    // the refusal names the directory, not the scene.
    test::CliRun r = test::runKiln("render /nonexistent/scene.dae -q -o /proc/out");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("'/proc' is not writable"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The bar is as wide as the terminal: rendered on a pseudo-terminal (util-linux script) of 60 and
// of 120 columns, every bar line fits, and the wider terminal gets the wider bar.
TEST(JobQueue, ProgressBarFitsTheTerminal) {
    if (test::runProgram("which", "script >/dev/null").code != 0) GTEST_SKIP() << "no script(1)";
    auto dir = test::scratchDir();
    std::map<int, size_t> widest;
    for (int cols : {60, 120}) {
        std::string inner = "stty cols " + std::to_string(cols) + "; " + KILN_BINARY + " render " +
                            test::repo("scenes/cornell.dae") + " -r 32 24 -s 8 -o " +
                            (dir / "bar").string();
        test::CliRun r =
            test::runProgram("script", "-q -e -c " + test::shellQuoted(inner) + " /dev/null");
        ASSERT_EQ(r.code, 0) << r.err;
        std::string line;
        std::istringstream all(r.out);
        while (std::getline(all, line, '\r'))
            if (line.rfind("render [", 0) == 0) {
                EXPECT_LT(line.size(), size_t(cols)) << line;
                widest[cols] = std::max(widest[cols], line.size());
            }
        EXPECT_GT(widest[cols], 0u) << r.out;
    }
    EXPECT_GT(widest[120], widest[60] + 40);
}

TEST(SvgPlot, HostileNamesStayValidXml) {
    std::string title = "R&D <\"plot\"> 'x'";
    std::string svg =
        svgLogLogPlot(title, "a<b", "c&d", {{"s&<1", {1, 2, 4}, {1, 0.5, 0.25}}}, true);
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(svg.c_str())) << svg;
    pugi::xml_node root = doc.child("svg");
    ASSERT_TRUE(root);
    std::vector<std::string> texts;
    for (pugi::xml_node t : root.children("text")) texts.push_back(t.text().get());
    EXPECT_NE(std::find(texts.begin(), texts.end(), title), texts.end());
    EXPECT_NE(std::find(texts.begin(), texts.end(), "s&<1"), texts.end());
    EXPECT_EQ(std::distance(root.children("polyline").begin(), root.children("polyline").end()), 1);
}

}  // namespace
}  // namespace kiln
