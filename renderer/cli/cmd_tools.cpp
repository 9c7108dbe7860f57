// kiln tools: mesh generators for scale tests.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/output_check.h"
#include "renderer/core/log.h"
#include "scene/importers.h"
#include "scene/mesh_tools.h"
#include "scene/scene_loader.h"

namespace kiln {

int runTools(const std::vector<std::string>& args) {
    if (args.empty() || args[0] != "subdivide")
        throw UsageError("usage: kiln tools subdivide IN OUT.ply|OUT.obj [--levels N]");
    ArgParser parser(
        "tools subdivide",
        "IN OUT.ply|OUT.obj [--levels N]   (1-to-4 midpoint subdivision; binary PLY or OBJ)");
    int levels = 1;
    parser.intOption("levels", "", "subdivision levels, each x4 triangles (default 1)", levels, 1,
                     8);
    std::vector<std::string> pos =
        parser.parse(std::vector<std::string>(args.begin() + 1, args.end()));
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 2) throw UsageError("needs IN and OUT.ply (or OUT.obj)");
    std::string ext = std::filesystem::path(pos[1]).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return char(std::tolower(ch)); });
    if (ext != ".ply" && ext != ".obj")
        throw UsageError(pos[1] + ": OUT is written as binary PLY or OBJ: name it .ply or .obj");
    // The input is read whole before OUT is written, but an OUT that is IN would replace it.
    if (std::error_code ec; std::filesystem::equivalent(pos[0], pos[1], ec))
        throw UsageError(pos[1] + ": OUT is IN; write the subdivided mesh to another file");
    checkOutputBase(pos[1]);
    checkOutputFiles({pos[1]});
    const bool obj = ext == ".obj";
    auto t0 = std::chrono::steady_clock::now();
    Scene scene = loadScene(pos[0]);
    // All world-space meshes joined into one (the scene was recentred: add the origin back).
    TriangleMesh joined;
    std::vector<bool> proto = scene.prototypeMask();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (proto[m]) continue;
        const TriangleMesh& mesh = scene.meshes[m];
        uint32_t base = uint32_t(joined.positions.size() / 3);
        for (size_t v = 0; v < mesh.vertexCount(); ++v) {
            Vec3 p = Vec3(Vec3d(mesh.vertex(uint32_t(v))) + scene.origin);
            joined.positions.insert(joined.positions.end(), {p.x, p.y, p.z});
        }
        for (uint32_t i : mesh.indices) joined.indices.push_back(base + i);
    }
    joined.materialIds = {0};
    checkMemoryFor(pos[1], uint64_t(joined.vertexCount()) << (2 * levels),
                   uint64_t(joined.triangleCount()) << (2 * levels));
    for (int l = 0; l < levels; ++l) joined = subdivideMidpoint(joined);
    if (obj)
        writeObj(pos[1], joined);
    else
        writeBinaryPly(pos[1], joined);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    logInfo("{}: {} vertices, {} triangles, {:.2f} s", pos[1], joined.vertexCount(),
            joined.triangleCount(), s);
    return 0;
}

}  // namespace kiln
