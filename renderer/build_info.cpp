#include "renderer/build_info.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenEXR/OpenEXRConfig.h>
#include <OpenImageIO/oiioversion.h>
#include <assimp/version.h>
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <oneapi/tbb/version.h>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <utility>
#include <vector>

#include "kiln_git_commit.h"  // generated in the build tree (CMakeLists.txt)

namespace kiln {
namespace {

std::vector<std::pair<std::string, std::string>> libraries() {
    return {
        {"embree", RTC_VERSION_STRING},
        {"OpenImageIO", OIIO_VERSION_STRING},
        {"OpenEXR", OPENEXR_VERSION_STRING},
        {"OpenColorIO", OCIO_NAMESPACE::GetVersion()},
        {"oneTBB", TBB_runtime_version()},
        {"assimp",
         fmt::format("{}.{}.{}", aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionPatch())},
        {"pugixml", fmt::format("{}.{}", PUGIXML_VERSION / 1000, PUGIXML_VERSION % 1000 / 10)},
        {"fmt",
         fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100)},
        {"nlohmann-json", fmt::format("{}.{}.{}", NLOHMANN_JSON_VERSION_MAJOR,
                                      NLOHMANN_JSON_VERSION_MINOR, NLOHMANN_JSON_VERSION_PATCH)},
    };
}

}  // namespace

std::string gitCommit() { return KILN_GIT_COMMIT; }

std::string libraryVersions() {
    std::string text;
    for (const auto& [name, version] : libraries())
        text += (text.empty() ? "" : ", ") + name + " " + version;
    return text;
}

std::string versionText() {
    std::string text = fmt::format("kiln {} (commit {})\n", KILN_VERSION, gitCommit());
    for (const auto& [name, version] : libraries())
        text += fmt::format("  {:<14}{}\n", name, version);
    return text;
}

}  // namespace kiln
