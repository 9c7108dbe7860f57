// kiln report cs184 end to end: the page, every image it names, the five parts and the BVH timing
// table; bad input refused before any rendering; the HTML writer's escaping.
#include <OpenImageIO/imageio.h>

#include <regex>

#include "renderer/cli/html_page.h"
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

TEST(Report, Cs184PageHasEveryPartAndEveryImageItNames) {
    auto dir = test::scratchDir() / "report";
    ASSERT_EQ(kiln("report cs184 " + test::cs184("sky/CBspheres_lambertian.dae") + " -o " +
                   dir.string() + " --budget 8 -t 2"),
              0);
    std::string page = readText(dir / "index.html");
    for (const char* part :
         {"Part 1: ray generation and intersection", "Part 2: direct lighting",
          "Part 3: global illumination", "Part 4: Russian roulette", "Part 5: adaptive sampling",
          "no BVH (--accel brute)", "reference BVH", "The m-th bounce only (-o 0)",
          "sample rate:", "indirect only", "uniform hemisphere (-H)", "-l 64", "-s 1024"})
        EXPECT_NE(page.find(part), std::string::npos) << part;
    std::regex img("<img src=\"([^\"]+)\"");
    int images = 0;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), img);
         it != std::sregex_iterator(); ++it) {
        std::string file = (dir / (*it)[1].str()).string();
        auto in = OIIO::ImageInput::open(file);
        ASSERT_TRUE(in) << file;
        EXPECT_GT(in->spec().width, 0);
        ++images;
    }
    // normals 1, direct 2 + 4, GI 3 + 7 + 6 + 6, roulette 2, adaptive 2
    EXPECT_EQ(images, 33);
    EXPECT_FALSE(std::filesystem::exists(dir / "index.html.tmp"));
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
    EXPECT_EQ(kiln("report cs184 " + scene + " /nonexistent/x.dae -o " + (dir / "r").string()), 2);
    EXPECT_FALSE(std::filesystem::exists(dir / "r" / "index.html"));
    EXPECT_EQ(kiln("report cs184 --help"), 0);
}

TEST(Report, HtmlPageEscapesEveryText) {
    HtmlPage page("a <b> & \"c\"");
    page.paragraph("<script>x</script>");
    page.images({{"im'g.png", "cap<", "-o 0 & 1"}});
    page.table({"h>"}, {{"<td>"}});
    std::string html = page.html();
    EXPECT_EQ(html.find("<script>"), std::string::npos);
    EXPECT_EQ(html.find("<b>"), std::string::npos);
    EXPECT_NE(html.find("&lt;script&gt;x&lt;/script&gt;"), std::string::npos);
    EXPECT_NE(html.find("src=\"im&#39;g.png\""), std::string::npos);
    EXPECT_NE(html.find("-o 0 &amp; 1"), std::string::npos);
    EXPECT_NE(html.find("<td>&lt;td&gt;</td>"), std::string::npos);
}

}  // namespace
}  // namespace kiln
