// The command line through CLI11 (renderer/cli/cli_args): the GNU forms (-s4, --spp=4, bundled
// switches, --), grouped help, one-line errors; and the log facade (renderer/core/log): levels,
// the "kiln: " prefix and JSON lines.
#include <nlohmann/json.hpp>
#include <sstream>

#include "kiln_run.h"
#include "renderer/cli/cli_args.h"
#include "renderer/cli/render_options.h"
#include "renderer/core/log.h"
#include "test_support.h"

namespace kiln {
namespace {

// The render job a command line describes, parsed by kiln render's own declarations.
struct Parsed {
    RenderJobArgs job;
    std::string output;
    bool quiet = false;
    std::vector<std::string> positional;
};

Parsed parseRender(const std::vector<std::string>& args) {
    Parsed p;
    ArgParser parser("render", "SCENE");
    p.job.addOptions(parser);
    addOutputNameOptions(parser, p.output, p.job.job.path);
    parser.flag("quiet", "q", "no progress bar", p.quiet);
    p.positional = parser.parse(args);
    return p;
}

TEST(CliParsing, AttachedSeparateAndEqualsValuesAreTheSame) {
    for (std::vector<std::string> args :
         {std::vector<std::string>{"-s4"}, {"-s", "4"}, {"--spp=4"}, {"--spp", "4"}}) {
        Parsed p = parseRender(args);
        EXPECT_EQ(p.job.job.settings.spp, 4) << args[0];
    }
    // Two-value options take both, attached or not; a later value overrides an earlier one.
    Parsed r = parseRender({"-r", "64", "48", "-s", "2", "--spp=3", "-m2"});
    EXPECT_EQ(r.job.job.settings.width, 64);
    EXPECT_EQ(r.job.job.settings.height, 48);
    EXPECT_EQ(r.job.job.settings.spp, 3);
    EXPECT_EQ(r.job.job.path.maxDepth, 2);
}

TEST(CliParsing, BundledSwitchesAndAValueAtTheEnd) {
    // -qH: -q and -H; -qHs8: both switches, then -s 8.
    Parsed p = parseRender({"-qHs8", "scene.dae"});
    EXPECT_TRUE(p.quiet);
    EXPECT_EQ(p.job.job.path.sampling, DirectSampling::Hemisphere);
    EXPECT_EQ(p.job.job.settings.spp, 8);
    EXPECT_EQ(p.positional, std::vector<std::string>{"scene.dae"});
}

TEST(CliParsing, DoubleDashEndsTheOptions) {
    Parsed p = parseRender({"-s", "2", "--", "-scene.dae", "-s"});
    EXPECT_EQ(p.job.job.settings.spp, 2);
    EXPECT_EQ(p.positional, (std::vector<std::string>{"-scene.dae", "-s"}));
    // Negative numbers are values, not options.
    Parsed crop = parseRender({"--crop", "0", "1", "0", "0.5", "-o", "-weird"});
    EXPECT_EQ(crop.output, "-weird");
}

TEST(CliParsing, CommandLineOrderDecides) {
    // -o 0 is CS184's accumulate switch; --bounce-only then -o 1 turns accumulation back on.
    EXPECT_FALSE(parseRender({"-o", "0"}).job.job.path.accumulateBounces);
    EXPECT_TRUE(parseRender({"--bounce-only", "-o", "1"}).job.job.path.accumulateBounces);
    EXPECT_FALSE(parseRender({"-o", "1", "--bounce-only"}).job.job.path.accumulateBounces);
    EXPECT_EQ(parseRender({"--output", "a", "-o", "b"}).output, "b");
}

std::string usageError(const std::vector<std::string>& args) {
    try {
        parseRender(args);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(CliParsing, BadFlagsAndValuesNameTheFlag) {
    EXPECT_EQ(usageError({"--bogus"}), "unknown option '--bogus' (see 'kiln render --help')");
    EXPECT_EQ(usageError({"-s0"}), "option --spp must be between 1 and 1048576, got 0");
    EXPECT_EQ(usageError({"--spp=many"}), "option --spp needs an integer, got 'many'");
    EXPECT_EQ(usageError({"--sampler", "halton"}),
              "--sampler takes independent|sobol, got 'halton'");
    EXPECT_EQ(usageError({"--heuristic=max"}), "--heuristic takes power|balance, got 'max'");
    std::string missing = usageError({"-r", "64"});
    EXPECT_NE(missing.find("--resolution"), std::string::npos) << missing;
    EXPECT_NE(missing.find("W H"), std::string::npos) << missing;
    for (const std::string& e : {missing, usageError({"--bogus"}), usageError({"-s", "x"})})
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(CliParsing, HelpIsGeneratedInGroups) {
    ArgParser parser("render", "SCENE");
    RenderJobArgs job;
    job.addOptions(parser);
    LoadOptions load;
    addLoadOptions(parser, load);
    parser.flag("extra", "", "a command's own switch, outside the shared groups",
                job.job.settings.progress);
    EXPECT_TRUE(parser.parse({"--help"}).empty());
    EXPECT_TRUE(parser.helpRequested());
    std::string help = parser.helpText();
    size_t last = 0;
    for (const char* group : {"Image:", "Sampling:", "Transport:", "Output:", "Scene:", "Options:",
                              "Messages:", "Help:"}) {
        size_t at = help.find(std::string("\n") + group + "\n");
        ASSERT_NE(at, std::string::npos) << group << "\n" << help;
        EXPECT_GT(at, last) << group;  // in the order declared
        last = at;
    }
    // Each option in its group: -s under Sampling, --camera under Scene, --extra under Options.
    auto groupOf = [&](const std::string& option) {
        size_t at = help.find(option);
        size_t header = help.rfind(":\n", at);
        return help.substr(help.rfind('\n', header - 1) + 1,
                           header - help.rfind('\n', header - 1) - 1);
    };
    EXPECT_EQ(groupOf("-s, --spp N"), "Sampling");
    EXPECT_EQ(groupOf("-r, --resolution W H"), "Image");
    EXPECT_EQ(groupOf("--camera file|framed"), "Scene");
    EXPECT_EQ(groupOf("--extra"), "Options");
    EXPECT_EQ(groupOf("--log-level error|warning|info|debug"), "Messages");
}

TEST(CliParsing, TheBinaryTakesTheNewFormsAndAFileNamedLikeAnOption) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file(test::repo("scenes/cornell.dae"), dir / "-box.dae");
    std::string kiln = "cd " + test::shellQuoted(dir.string()) + " && " + KILN_BINARY;
    test::CliRun r =
        test::runProgram(kiln, "render -r 16 12 -s2 -qt1 --aov=none -o out -- -box.dae");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out.exr"));
    EXPECT_NE(r.err.find("-box.dae -> out.exr"), std::string::npos) << r.err;
    test::CliRun help = test::runKiln("render --help");
    for (const char* group : {"\nImage:\n", "\nSampling:\n", "\nTransport:\n", "\nOutput:\n",
                              "\nScene:\n", "\nCamera:\n", "\nMessages:\n"})
        EXPECT_NE(help.out.find(group), std::string::npos) << group;
    test::CliRun bad = test::runKiln("render x.dae --compression=lzma");
    EXPECT_EQ(bad.code, 2);
    EXPECT_EQ(bad.err,
              "kiln render: --compression takes "
              "none|rle|zip|zips|piz|pxr24|b44|b44a|dwaa|dwab, got 'lzma'\n");
}

// Captures the log's lines for one scope and puts the level, format and sink back after.
struct CapturedLog {
    std::vector<std::string> lines;
    LogSink previous;
    LogLevel level = logLevel();
    CapturedLog() {
        previous = setLogSink([this](const std::string& line) { lines.push_back(line); });
    }
    ~CapturedLog() {
        setLogSink(previous);
        setLogLevel(level);
        setLogFormat(LogFormat::Text);
    }
};

TEST(Log, TextLinesHaveOnePrefixAndTheirLabel) {
    CapturedLog log;
    setLogLevel(LogLevel::Debug);
    logError("{} is bad", "x.obj");
    logWarning("{:.1f} % dropped", 2.25);
    logInfo("{} samples", 42);
    logDebug("tile {}", 7);
    logMessage(LogLevel::Error, "unknown option '--x'", "render");
    EXPECT_EQ(log.lines, (std::vector<std::string>{"kiln: error: x.obj is bad\n",
                                                   "kiln: warning: 2.2 % dropped\n",
                                                   "kiln: 42 samples\n", "kiln: debug: tile 7\n",
                                                   "kiln render: unknown option '--x'\n"}));
}

TEST(Log, LevelsFilter) {
    CapturedLog log;
    auto all = [] {
        logError("e");
        logWarning("w");
        logInfo("i");
        logDebug("d");
    };
    std::vector<size_t> counts;
    for (LogLevel level : {LogLevel::Error, LogLevel::Warning, LogLevel::Info, LogLevel::Debug}) {
        log.lines.clear();
        setLogLevel(level);
        all();
        counts.push_back(log.lines.size());
    }
    EXPECT_EQ(counts, (std::vector<size_t>{1, 2, 3, 4}));
    setLogLevel(LogLevel::Warning);
    log.lines.clear();
    all();
    EXPECT_EQ(log.lines, (std::vector<std::string>{"kiln: error: e\n", "kiln: warning: w\n"}));
}

TEST(Log, JsonLinesParseWhateverTheMessageHolds) {
    CapturedLog log;
    setLogFormat(LogFormat::JsonLines);
    std::string hostile = "q\"uo\\te\nnew line \xff\xfe bytes";
    logWarning("{}: zero-area triangles", hostile);
    logInfo("{} rays", 1000);
    logMessage(LogLevel::Error, "bad flag", "render");
    ASSERT_EQ(log.lines.size(), 3u);
    std::vector<nlohmann::json> parsed;
    for (const std::string& line : log.lines) {
        EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;  // one line each
        parsed.push_back(nlohmann::json::parse(line));
    }
    EXPECT_EQ(parsed[0]["event"], "log");
    EXPECT_EQ(parsed[0]["level"], "warning");
    // Invalid UTF-8 becomes U+FFFD; quotes, backslashes and the newline survive.
    EXPECT_EQ(parsed[0]["message"],
              "q\"uo\\te\nnew line \xef\xbf\xbd\xef\xbf\xbd bytes: zero-area triangles");
    EXPECT_EQ(parsed[1]["level"], "info");
    EXPECT_EQ(parsed[1]["message"], "1000 rays");
    EXPECT_EQ(parsed[2]["level"], "error");
    EXPECT_EQ(parsed[2]["command"], "render");
}

TEST(Log, TheBinarysLogLevelAndJsonModes) {
    auto dir = test::scratchDir();
    std::string render = "render " + test::repo("scenes/cornell.dae") + " -r 16 12 -s 2 -q -o " +
                         (dir / "box").string();
    // --log-level warning: the summary lines (info) are gone, the render is the same.
    test::CliRun quiet = test::runKiln(render + " --log-level warning");
    ASSERT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "");
    EXPECT_EQ(test::runKiln(render + " --log-level loud").code, 2);
    // --progress json: every line on stderr is a JSON object, the summary among them.
    test::CliRun json = test::runKiln(render + " --progress json");
    ASSERT_EQ(json.code, 0) << json.err;
    std::istringstream err(json.err);
    int logLines = 0;
    for (std::string line; std::getline(err, line);) {
        nlohmann::json j = nlohmann::json::parse(line);  // throws (fails) on any other line
        if (j["event"] == "log") {
            ++logLines;
            EXPECT_EQ(j["level"], "info") << line;
        }
    }
    EXPECT_GE(logLines, 3) << json.err;
    EXPECT_NE(json.err.find("Mrays/s"), std::string::npos);
}

}  // namespace
}  // namespace kiln
