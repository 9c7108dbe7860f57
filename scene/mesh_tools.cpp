#include "scene/mesh_tools.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <unordered_map>

#include "color/atomic_file.h"

namespace kiln {

TriangleMesh subdivideMidpoint(const TriangleMesh& mesh) {
    TriangleMesh out;
    out.name = mesh.name;
    out.materialIds = mesh.materialIds.size() == 1 ? mesh.materialIds : std::vector<uint32_t>{};
    size_t nv = mesh.vertexCount();
    out.positions.assign(mesh.positions.begin(), mesh.positions.begin() + long(3 * nv));
    out.positions.reserve(3 * (nv + 2 * mesh.triangleCount()) + 1);
    out.indices.reserve(4 * mesh.indices.size());
    std::unordered_map<uint64_t, uint32_t> midpoints;
    midpoints.reserve(mesh.triangleCount() * 3 / 2 + 1);
    auto midpoint = [&](uint32_t a, uint32_t b) {
        uint64_t key = a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
        auto [it, inserted] = midpoints.try_emplace(key, uint32_t(out.positions.size() / 3));
        if (inserted) {
            Vec3 m = (mesh.vertex(a) + mesh.vertex(b)) * 0.5f;
            out.positions.insert(out.positions.end(), {m.x, m.y, m.z});
        }
        return it->second;
    };
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
        uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
        out.indices.insert(out.indices.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        if (out.materialIds.empty())
            out.materialIds.insert(out.materialIds.end(), 4, mesh.materialOf(t));
    }
    out.finalizePadding();
    return out;
}

void writeBinaryPly(const std::string& path, const TriangleMesh& mesh) {
    AtomicFile file(path);  // temporary, checked writes, fsync, rename
    std::string header = fmt::format(
        "ply\nformat binary_little_endian 1.0\ncomment written by kiln\nelement vertex {}\n"
        "property float x\nproperty float y\nproperty float z\nelement face {}\n"
        "property list uchar int vertex_indices\nend_header\n",
        mesh.vertexCount(), mesh.triangleCount());
    file.write(header.data(), header.size());
    file.write(mesh.positions.data(), sizeof(float) * 3 * mesh.vertexCount());
    std::vector<unsigned char> faces(13 * std::min<size_t>(mesh.triangleCount(), 1 << 16));
    for (size_t t = 0; t < mesh.triangleCount();) {
        size_t k = 0;
        for (; k < faces.size() / 13 && t < mesh.triangleCount(); ++k, ++t) {
            faces[13 * k] = 3;
            std::memcpy(&faces[13 * k + 1], &mesh.indices[3 * t], 12);
        }
        file.write(faces.data(), 13 * k);
    }
    file.commit();
}

void writeObj(const std::string& path, const TriangleMesh& mesh) {
    AtomicFile file(path);   // temporary, checked writes, fsync, rename
    fmt::memory_buffer buf;  // shortest round-trip floats, as std::to_chars
    auto flush = [&] {
        file.write(buf.data(), buf.size());
        buf.clear();
    };
    const float* p = mesh.positions.data();
    for (size_t v = 0; v < mesh.vertexCount(); ++v, p += 3) {
        fmt::format_to(std::back_inserter(buf), "v {} {} {}\n", p[0], p[1], p[2]);
        if (buf.size() > (1 << 20)) flush();
    }
    const auto* index = mesh.indices.data();
    for (size_t t = 0; t < mesh.triangleCount(); ++t, index += 3) {
        fmt::format_to(std::back_inserter(buf), "f {} {} {}\n", index[0] + 1, index[1] + 1,
                       index[2] + 1);
        if (buf.size() > (1 << 20)) flush();
    }
    flush();
    file.commit();
}

}  // namespace kiln
