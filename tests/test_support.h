// Paths and small helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "renderer/render_job.h"
#include "scene/scene.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

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

// $KILN_MEMORY_LIMIT set for one scope and cleared however the scope is left, so a failing test
// cannot leave the limit on for the tests after it.
struct ScopedMemoryLimit {
    explicit ScopedMemoryLimit(const char* bytes) { ::setenv("KILN_MEMORY_LIMIT", bytes, 1); }
    ~ScopedMemoryLimit() { ::unsetenv("KILN_MEMORY_LIMIT"); }
    ScopedMemoryLimit(const ScopedMemoryLimit&) = delete;
    ScopedMemoryLimit& operator=(const ScopedMemoryLimit&) = delete;
};

// The options of a quiet w x h render at spp, beauty only unless aovs say more.
inline RenderJobOptions jobOptions(int w, int h, int spp, const PathOptions& path = {},
                                   const AovRequest& aovs = {}) {
    RenderJobOptions o;
    o.path = path;
    o.aovs = aovs;
    o.settings.width = w, o.settings.height = h, o.settings.spp = spp;
    o.settings.progress = false;
    return o;
}

// One render through RenderJob, exactly as kiln render sets it up.
inline Film renderJob(const Scene& s, const Accelerator& accel, const RenderJobOptions& options,
                      RenderStats* stats = nullptr) {
    RenderJob job(s, accel, options);
    Film film = job.makeFilm();
    RenderStats done = job.render(film);
    if (stats) *stats = done;
    return film;
}

// The index of an AOV channel ("albedo.R", "P.X") in the film's layout.
inline size_t aovChannel(const Film& f, const std::string& name) {
    const auto& ch = f.layout().channels();
    for (size_t i = 0; i < ch.size(); ++i)
        if (ch[i].name == name) return i;
    ADD_FAILURE() << "no channel " << name;
    return 0;
}

// Expects loadScene to throw a one-line SceneError that names the file first and contains `what`.
inline void expectError(const std::string& path, const std::string& what) {
    try {
        loadScene(path);
        ADD_FAILURE() << "no error for " << path;
    } catch (const SceneError& e) {
        std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        EXPECT_EQ(msg.rfind(path, 0), 0u) << "message does not start with the file: " << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
    }
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
// How many of the scene's warnings name `text`.
inline int warningsNaming(const Scene& s, const std::string& text) {
    int n = 0;
    for (const std::string& w : s.warnings) n += w.find(text) != std::string::npos;
    return n;
}
inline bool hasWarning(const Scene& s, const std::string& text) {
    return warningsNaming(s, text) > 0;
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

// Geometry builders for tests.
// A w x h grid of unit squares in the z = 0 plane, two triangles each, shared vertices.
inline TriangleMesh gridMesh(int w, int h, float cell = 1.0f) {
    TriangleMesh m;
    m.name = "grid";
    for (int y = 0; y <= h; ++y)
        for (int x = 0; x <= w; ++x)
            m.positions.insert(m.positions.end(), {x * cell, y * cell, 0.0f});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint32_t a = uint32_t(y * (w + 1) + x), b = a + 1, c = a + uint32_t(w) + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    m.materialIds = {0};
    m.finalizePadding();
    return m;
}

// A UV sphere of radius 1 at the origin (closed, shared vertices).
inline TriangleMesh sphereMesh(int rings, int segments) {
    TriangleMesh m;
    m.name = "uvsphere";
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < segments; ++s) {
            float th = kPi * r / rings, ph = 2 * kPi * s / segments;
            m.positions.insert(m.positions.end(), {std::sin(th) * std::cos(ph), std::cos(th),
                                                   std::sin(th) * std::sin(ph)});
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            uint32_t a = uint32_t(r * segments + s),
                     b = uint32_t(r * segments + (s + 1) % segments);
            uint32_t c = a + uint32_t(segments), d = b + uint32_t(segments);
            if (r > 0) m.indices.insert(m.indices.end(), {a, c, b});
            if (r < rings - 1) m.indices.insert(m.indices.end(), {b, c, d});
        }
    m.materialIds = {0};
    m.finalizePadding();
    return m;
}

// A closed tetrahedron as an OBJ file at path (wound outwards): the smallest mesh with an inside.
inline std::string writeTetrahedronObj(const std::filesystem::path& path) {
    return writeFile(path,
                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
}

// The white furnace's sky: an environment light without an image, radiance 1 from everywhere.
inline Light uniformEnvironment() {
    Light env;
    env.kind = LightKind::Environment;
    env.radiance = Color(1.0f);
    return env;
}

inline Scene sceneWith(TriangleMesh mesh) {
    Scene s;
    s.sourcePath = "test";
    s.materials.push_back(Material{"m"});
    s.meshes.push_back(std::move(mesh));
    return s;
}

}  // namespace kiln::test
