// kiln report cs184 end to end: the course's parts and tasks in order, every image it names, every
// caption the command that made the image (two of them run again as kiln render), no degenerate
// experiment; the planner's budget fitting; bad input refused before any rendering; the page
// writer's escaping and its Markdown.
#include <OpenImageIO/imageio.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "renderer/cli/cs184_figures.h"
#include "renderer/cli/cs184_planner.h"
#include "renderer/cli/report_page.h"
#include "test_support.h"

namespace kiln {
namespace {

int kiln(const std::string& args) {
    return std::system((std::string(KILN_BINARY) + " " + args + " >/dev/null 2>&1").c_str()) >> 8;
}

std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<float> pixels(const std::string& file) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> p(size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, p.data());
    return p;
}

std::string unescape(std::string s) {
    for (auto [from, to] :
         {std::pair{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&#39;", "'"}, {"&amp;", "&"}})
        for (size_t at; (at = s.find(from)) != std::string::npos;)
            s.replace(at, std::string(from).size(), to);
    return s;
}

// One report, shared by the tests that read it: a tiny budget, one scene, cow for the BVH table.
struct SmallReport {
    std::filesystem::path dir;
    std::string page;
    nlohmann::json json;
};

SmallReport runSmallReport() {
    {
        SmallReport s;
        s.dir = test::scratchDir() / "report";
        int status = kiln("report cs184 " + test::cs184("sky/CBspheres_lambertian.dae") + " -o " +
                          s.dir.string() + " --budget 12 -t 1 --bvh-scenes " +
                          test::cs184("meshedit/cow.dae"));
        EXPECT_EQ(status, 0);
        s.page = readText(s.dir / "index.html");
        std::ifstream in(s.dir / "report.json");
        if (in) s.json = nlohmann::json::parse(in);
        return s;
    }
}

void checkPageHasTheCoursesPartsAndTasksInOrder(const SmallReport& r) {
    size_t at = 0;
    for (const cs184::Task& t : cs184::courseTasks()) {
        std::string tag = t.task == 0 ? "h2" : "h3";
        size_t found = r.page.find("<" + tag + ">" + t.heading + "</" + tag + ">", at);
        ASSERT_NE(found, std::string::npos) << t.heading << " (in order)";
        at = found;
    }
    // Every figure discussed: a paragraph follows every image row.
    std::regex rowThenParagraph("</div>\n<p>");
    EXPECT_EQ(std::distance(std::sregex_iterator(r.page.begin(), r.page.end(), rowThenParagraph),
                            std::sregex_iterator()),
              long(cs184::courseFigures().size()) + 1);  // + the BVH meshes' row
    // Offline: no remote asset.
    EXPECT_EQ(r.page.find("http:"), std::string::npos);
    EXPECT_EQ(r.page.find("https:"), std::string::npos);
}

void checkEveryImageDecodesAndEveryCaptionIsTheCommandRun(const SmallReport& r) {
    std::regex img("<img src=\"([^\"]+)\"");
    int images = 0;
    for (auto it = std::sregex_iterator(r.page.begin(), r.page.end(), img);
         it != std::sregex_iterator(); ++it, ++images)
        EXPECT_FALSE(pixels((r.dir / (*it)[1].str()).string()).empty()) << (*it)[1];
    EXPECT_GT(images, 30);
    std::set<std::string> run;
    for (const auto& s : r.json["shots"]) run.insert(s["command"].get<std::string>());
    for (const auto& s : r.json["timings"]) run.insert(s["command"].get<std::string>());
    std::regex code("<code>(kiln render [^<]*)</code>");
    int captions = 0;
    for (auto it = std::sregex_iterator(r.page.begin(), r.page.end(), code);
         it != std::sregex_iterator(); ++it, ++captions) {
        std::string command = unescape((*it)[1].str());
        command = command.substr(0, command.find("  ("));  // "  (the direct layer of its EXR)"
        EXPECT_TRUE(run.count(command)) << command;
    }
    EXPECT_EQ(captions, images);
    // Where the budget cut the course's samples the caption says so.
    for (const auto& s : r.json["shots"])
        if (s["spp"] != s["course_spp"] && s["layer"] == "") {
            EXPECT_NE(r.page.find("the course uses -s " + std::to_string(int(s["course_spp"]))),
                      std::string::npos);
        }
}

// The caption run again by kiln render itself writes the image the page shows.
void checkCaptionRunAsKilnRenderGivesThePagesImage(const SmallReport& r) {
    auto again = r.dir.parent_path() / "again";
    std::filesystem::create_directories(again);
    for (const auto& s : r.json["shots"]) {
        if (s["figure"] != "normals" && s["figure"] != "adaptive") continue;
        std::string command = s["command"], file = s["file"];
        std::string pagePng = (r.dir / file).string(), newPng = (again / file).string();
        command.replace(command.find(pagePng), pagePng.size(), newPng);
        ASSERT_EQ(kiln(command.substr(std::string("kiln ").size()) + " -q"), 0) << command;
        EXPECT_EQ(pixels(newPng), pixels(pagePng)) << command;
        if (s["rate_file"] != "") {
            EXPECT_EQ(pixels((again / s["rate_file"].get<std::string>()).string()),
                      pixels((r.dir / s["rate_file"].get<std::string>()).string()));
        }
    }
}

void checkNoExperimentIsDegenerate(const SmallReport& r) {
    int adaptive = 0;
    for (const auto& s : r.json["shots"]) {
        if (s["batch"] == 0) continue;
        ++adaptive;
        EXPECT_GE(int(s["spp"]), 4 * int(s["batch"]));
        EXPECT_LT(s["min_spp"], s["max_spp"]);
        std::vector<float> rate = pixels((r.dir / s["rate_file"].get<std::string>()).string());
        ASSERT_FALSE(rate.empty());
        EXPECT_NE(*std::min_element(rate.begin(), rate.end()),
                  *std::max_element(rate.begin(), rate.end()));
    }
    EXPECT_EQ(adaptive, 1);
    ASSERT_EQ(r.json["timings"].size(), 3u);  // Embree, the course's BVH, none
    for (const auto& t : r.json["timings"])
        EXPECT_GE(t["seconds"].get<double>(), r.json["timing_floor_seconds"].get<double>())
            << t["command"];
}

// One run (a tiny budget keeps it short) checked five ways.
TEST(Report, Cs184WriteUpFollowsTheCourseWithTrueCaptionsAndNoDegenerateExperiment) {
    SmallReport r = runSmallReport();
    ASSERT_FALSE(r.page.empty());
    ASSERT_FALSE(r.json.empty());
    {
        SCOPED_TRACE("parts and tasks");
        checkPageHasTheCoursesPartsAndTasksInOrder(r);
    }
    {
        SCOPED_TRACE("captions");
        checkEveryImageDecodesAndEveryCaptionIsTheCommandRun(r);
    }
    {
        SCOPED_TRACE("captions run again");
        checkCaptionRunAsKilnRenderGivesThePagesImage(r);
    }
    {
        SCOPED_TRACE("degenerate experiments");
        checkNoExperimentIsDegenerate(r);
    }
    {
        SCOPED_TRACE("threads");  // -t 1 bounds Embree's build too, as it does a render's
        EXPECT_EQ(r.json["threads"], 1);
        EXPECT_EQ(r.json["embree_build_threads"], 1);
    }
}

TEST(Report, PlannerFitsTheSecondsAndKeepsAdaptiveAboveItsBatch) {
    std::vector<cs184::Figure> figures = cs184::courseFigures();
    cs184::Planner planner(figures, 1);
    planner.throughput(0).record("-l 4 -m 5", 1e6, 0.1);  // 10 Mrays/s
    std::vector<size_t> all;
    for (size_t i = 0; i < figures.size(); ++i) all.push_back(i);
    cs184::Size size{480, 360};
    const double least = planner.secondsNeeded(size);
    for (double seconds : {least * 1.5, least * 4, least * 20}) {
        double scale = planner.fitScale(all, size, seconds);
        EXPECT_LE(planner.predict(all, size, scale), seconds * 1.0001);
        if (scale > cs184::kMinScale && scale < 1) {  // the fit spends what it may, to 1 %
            EXPECT_GT(planner.predict(all, size, scale * 1.01), seconds);
        }
    }
    EXPECT_GT(planner.secondsNeeded({640, 480}), planner.secondsNeeded({480, 360}));
    EXPECT_EQ(planner.chooseSize(planner.secondsNeeded({480, 360}) * 1.01).width, 480);
    for (const cs184::Figure& f : figures)
        for (const cs184::Shot& s : f.shots)
            for (double scale : {cs184::kFloorScale, cs184::kMinScale, 0.1, 1.0}) {
                cs184::ShotPlan p = cs184::planShot(s, scale, 16);
                if (s.courseBatch > 0) {
                    EXPECT_GE(p.spp, 4 * p.batch) << scale;
                }
                if (s.rule == cs184::SppRule::Scaled) {
                    EXPECT_GE(p.spp, 1);
                }
            }
}

TEST(Report, BadInputIsRefusedBeforeRendering) {
    auto dir = test::scratchDir();
    std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    EXPECT_EQ(kiln("report"), 2);
    EXPECT_EQ(kiln("report pbrt " + scene + " -o " + dir.string()), 2);
    EXPECT_EQ(kiln("report cs184 -o " + dir.string()), 2);
    EXPECT_EQ(kiln("report cs184 " + scene), 2);
    EXPECT_EQ(kiln("report cs184 " + scene + " -o " + dir.string() + " --budget 1"), 2);
    EXPECT_EQ(kiln("report cs184 " + scene + " -o " + dir.string() + " --view Nope"), 2);
    EXPECT_EQ(kiln("report cs184 " + scene + " -o " + dir.string() + " --format pdf"), 2);
    EXPECT_EQ(kiln("report cs184 " + scene + " -o " + dir.string() + " --bvh-scenes /no/cow.dae"),
              2);
    EXPECT_EQ(kiln("report cs184 " + scene + " /nonexistent/x.dae -o " + (dir / "r").string()), 2);
    EXPECT_FALSE(std::filesystem::exists(dir / "r" / "index.html"));
    EXPECT_EQ(kiln("report cs184 --help"), 0);
}

TEST(Report, PageEscapesEveryTextInHtmlAndMarkdown) {
    ReportPage page("a <b> & \"c\"");
    page.heading(2, "Part 1: x_y");
    page.paragraph("<script>x</script>");
    page.images({{"im'g.png", "cap<", "-o 0 & 1"}});
    page.table({"h>"}, {{"<td>", "a|b"}});
    std::string html = page.html();
    EXPECT_EQ(html.find("<script>"), std::string::npos);
    EXPECT_EQ(html.find("<b>"), std::string::npos);
    EXPECT_NE(html.find("&lt;script&gt;x&lt;/script&gt;"), std::string::npos);
    EXPECT_NE(html.find("src=\"im&#39;g.png\""), std::string::npos);
    EXPECT_NE(html.find("-o 0 &amp; 1"), std::string::npos);
    EXPECT_NE(html.find("<td>&lt;td&gt;</td>"), std::string::npos);
    std::string md = page.markdown();
    EXPECT_NE(md.find("## Part 1: x\\_y\n"), std::string::npos);
    EXPECT_NE(md.find("![cap\\<](im'g.png)"), std::string::npos);
    EXPECT_NE(md.find("`-o 0 & 1`"), std::string::npos);
    EXPECT_NE(md.find("| \\<td\\> | a\\|b |"), std::string::npos);  // a '|' cannot split a cell
    EXPECT_NE(md.find("\\<script\\>"), std::string::npos);
}

}  // namespace
}  // namespace kiln
