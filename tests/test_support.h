// Paths and small helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scene/scene.h"

namespace kiln::test {

// ../shared beside the repository (CI has it); tests fail, not skip, when it is missing.
inline std::string shared(const std::string& rel) {
    std::string p = std::string(KILN_SHARED_DIR) + "/" + rel;
    EXPECT_TRUE(std::filesystem::exists(p)) << "missing shared data: " << p;
    return p;
}
inline std::string cs184(const std::string& rel) { return shared("scenes/cs184/" + rel); }
inline std::string repo(const std::string& rel) { return std::string(KILN_SOURCE_DIR) + "/" + rel; }

// A fresh scratch directory per test.
inline std::filesystem::path scratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    auto dir = std::filesystem::temp_directory_path() / "kiln-tests" /
               (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

inline int countKind(const Scene& s, MaterialKind kind) {
    int n = 0;
    for (const Material& m : s.materials) n += m.kind == kind;
    return n;
}
inline const Light* findLight(const Scene& s, LightKind kind) {
    for (const Light& l : s.lights)
        if (l.kind == kind) return &l;
    return nullptr;
}
inline const Material* findMaterial(const Scene& s, MaterialKind kind, int nth = 0) {
    for (const Material& m : s.materials)
        if (m.kind == kind && nth-- == 0) return &m;
    return nullptr;
}

}  // namespace kiln::test
