// A direct, multi-threaded OBJ reader for geometry-only files (v, vn, vt, f, o, g, s, comments).
// The file is cut into chunks at line starts; a first parallel pass counts each chunk's vertices
// and triangles (so memory is checked before anything is allocated and every chunk knows where its
// output goes), a second parses the chunks in parallel straight into the mesh arrays. Files that
// use materials, free-form geometry or per-corner attribute indices that differ from the position
// index are left to Assimp (readObj returns false).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstdio>
#include <string_view>

#include "renderer/core/log.h"
#include "scene/importers.h"
#include "scene/mapped_file.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

constexpr size_t kChunkBytes = size_t(1) << 22;

struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;
    // Counted by the first pass; prefix sums turn them into output offsets.
    uint64_t lines = 0, positions = 0, normals = 0, uvs = 0, triangles = 0;
    uint64_t corners = 0, cornersWithUv = 0, cornersWithNormal = 0;
    bool unsupported = false;
    // Each 'o' or 'g' line starts a new mesh (as Assimp does): its name and the chunk's triangle
    // count at that point.
    std::vector<std::pair<uint64_t, std::string>> groups;
    // Offsets (first line number, first vertex, ... of this chunk in the whole file).
    uint64_t lineBase = 0, positionBase = 0, normalBase = 0, uvBase = 0, triangleBase = 0;
};

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

const char* skipBlanks(const char* p, const char* end) {
    while (p < end && isBlank(*p)) ++p;
    return p;
}

const char* tokenEnd(const char* p, const char* end) {
    while (p < end && !isBlank(*p) && *p != '\n') ++p;
    return p;
}

// The statements the direct reader understands; anything else sends the file to Assimp.
enum class Statement { Position, Normal, Uv, Face, Group, Ignored, Unsupported };

Statement classify(std::string_view key) {
    if (key == "v") return Statement::Position;
    if (key == "vn") return Statement::Normal;
    if (key == "vt") return Statement::Uv;
    if (key == "f") return Statement::Face;
    if (key == "o" || key == "g") return Statement::Group;
    if (key == "s") return Statement::Ignored;
    return Statement::Unsupported;  // mtllib, usemtl, l, p, curv, surf, vp, ...
}

// Calls fn(statement, first byte after the keyword, line end) for every non-empty, non-comment
// line of the chunk, and counts lines.
template <typename Fn>
void forEachLine(Chunk& c, Fn&& fn) {
    const char* p = c.begin;
    while (p < c.end) {
        const char* nl = static_cast<const char*>(std::memchr(p, '\n', size_t(c.end - p)));
        const char* lineEnd = nl ? nl : c.end;
        // A comment may also end a statement ("f 1 2 3 # top").
        const char* hash = static_cast<const char*>(std::memchr(p, '#', size_t(lineEnd - p)));
        const char* statementEnd = hash ? hash : lineEnd;
        const char* s = skipBlanks(p, statementEnd);
        if (s < statementEnd) {
            const char* k = tokenEnd(s, statementEnd);
            fn(classify(std::string_view(s, size_t(k - s))), k, statementEnd);
        }
        ++c.lines;
        p = lineEnd + 1;
    }
}

void countChunk(Chunk& c) {
    forEachLine(c, [&](Statement st, const char* start, const char* end) {
        // A trailing backslash continues the line: not handled here.
        const char* last = end;
        while (last > start && (last[-1] == '\r' || last[-1] == ' ')) --last;
        if (last > start && last[-1] == '\\') c.unsupported = true;
        const char* p = start;
        switch (st) {
            case Statement::Position:
                ++c.positions;
                break;
            case Statement::Normal:
                ++c.normals;
                break;
            case Statement::Uv:
                ++c.uvs;
                break;
            case Statement::Face: {
                uint64_t n = 0;
                for (p = skipBlanks(p, end); p < end; p = skipBlanks(p, end)) {
                    const char* e = tokenEnd(p, end);
                    const char* s1 = static_cast<const char*>(std::memchr(p, '/', size_t(e - p)));
                    if (s1) {
                        const char* s2 =
                            static_cast<const char*>(std::memchr(s1 + 1, '/', size_t(e - s1 - 1)));
                        c.cornersWithUv += (s2 ? s2 : e) > s1 + 1;
                        c.cornersWithNormal += s2 && e > s2 + 1;
                    }
                    ++n;
                    p = e;
                }
                c.corners += n;
                c.triangles += n >= 3 ? n - 2 : 0;
                break;
            }
            case Statement::Group: {
                p = skipBlanks(p, end);
                const char* e = end;
                while (e > p && isBlank(e[-1])) --e;
                c.groups.emplace_back(c.triangles, std::string(p, size_t(e - p)));
                break;
            }
            case Statement::Ignored:
                break;
            case Statement::Unsupported:
                c.unsupported = true;
                break;
        }
    });
}

class ChunkParser {
  public:
    ChunkParser(const std::string& path, Chunk& c, TriangleMesh& mesh, uint64_t totalPositions,
                bool useNormals, bool useUvs, const Vec3d& origin = Vec3d(0.0),
                bool useColours = false)
        : path_(path),
          c_(c),
          mesh_(mesh),
          origin_(origin),
          totalPositions_(totalPositions),
          useNormals_(useNormals),
          useUvs_(useUvs),
          useColours_(useColours) {}

    // False when a corner's normal or uv index differs from its position index.
    bool parse() {
        uint64_t positions = c_.positionBase, normals = c_.normalBase, uvs = c_.uvBase;
        uint64_t triangle = c_.triangleBase;
        bool sameIndices = true;
        c_.lines = 0;
        forEachLine(c_, [&](Statement st, const char* p, const char* end) {
            switch (st) {
                case Statement::Position: {
                    double xyz[3];
                    const char* rest = readNumbers(p, end, xyz, 3, 3);
                    if (useColours_) readColour(rest, end, &mesh_.colors[3 * positions]);
                    // Parsed in double, stored in float relative to the origin (far coordinates).
                    float* out = &mesh_.positions[3 * positions++];
                    for (int k = 0; k < 3; ++k) out[k] = float(xyz[k] - origin_[k]);
                    break;
                }
                case Statement::Normal:
                    if (useNormals_) readNumbers(p, end, &mesh_.normals[3 * normals], 3, 3);
                    ++normals;
                    break;
                case Statement::Uv:
                    if (useUvs_) readNumbers(p, end, &mesh_.uvs[2 * uvs], 1, 2);
                    ++uvs;
                    break;
                case Statement::Face: {
                    uint32_t first = 0, prev = 0;
                    int n = 0;
                    for (p = skipBlanks(p, end); p < end; p = skipBlanks(p, end)) {
                        const char* e = tokenEnd(p, end);
                        uint32_t idx[3] = {UINT32_MAX, UINT32_MAX, UINT32_MAX};
                        uint64_t counts[3] = {positions, uvs, normals};
                        for (int k = 0; k < 3 && p < e; ++k) {
                            if (*p != '/') p = readIndex(p, e, counts[k], idx[k]);
                            if (p < e && *p == '/') ++p;
                        }
                        if ((useNormals_ && idx[2] != idx[0]) || (useUvs_ && idx[1] != idx[0]))
                            sameIndices = false;
                        if (n >= 2) {
                            uint32_t* out = &mesh_.indices[3 * triangle++];
                            out[0] = first, out[1] = prev, out[2] = idx[0];
                        }
                        if (n == 0) first = idx[0];
                        prev = idx[0];
                        ++n;
                        p = e;
                    }
                    if (n < 3) fail("face with fewer than 3 vertices");
                    break;
                }
                default:
                    break;
            }
        });
        return sameIndices;
    }

  private:
    [[noreturn]] void fail(const std::string& what) const {
        throw SceneError(path_, "line " + std::to_string(c_.lineBase + c_.lines + 1) + ": " + what);
    }

    // Out of line: inlined into readNumbers, GCC 12 reports a false -Wrestrict on the message.
    [[noreturn, gnu::noinline]] void failNotANumber(const char* p, const char* e) const {
        fail("'" + std::string(p, size_t(e - p)) + "' is not a number");
    }

    // `want` numbers, of which the first `need` must be present (vt may omit v).
    template <typename T>
    const char* readNumbers(const char* p, const char* end, T* out, int need, int want) {
        for (int i = 0; i < want; ++i) {
            p = skipBlanks(p, end);
            if (p >= end) {
                if (i < need) fail("expected " + std::to_string(need) + " numbers");
                out[i] = 0;
                continue;
            }
            const char* e = tokenEnd(p, end);
            auto [next, ec] = std::from_chars(p, e, out[i]);
            if (ec != std::errc() || next != e) failNotANumber(p, e);
            p = e;
        }
        return p;
    }

    // "v x y z r g b": the colour after the position, linear as written; a vertex without one is
    // white (MeshLab and ZBrush write it on every vertex or none).
    void readColour(const char* p, const char* end, float* rgb) {
        if (skipBlanks(p, end) >= end)
            rgb[0] = rgb[1] = rgb[2] = 1.0f;
        else
            readNumbers(p, end, rgb, 3, 3);
    }

    // A 1-based (or negative, relative to `defined`) OBJ index into a 0-based one.
    const char* readIndex(const char* p, const char* e, uint64_t defined, uint32_t& out) {
        int64_t v = 0;
        auto [next, ec] = std::from_chars(p, e, v);
        if (ec != std::errc() || (next < e && *next != '/'))
            fail("bad vertex index '" + std::string(p, size_t(e - p)) + "'");
        int64_t i = v > 0 ? v - 1 : int64_t(defined) + v;
        if (v == 0 || i < 0 || uint64_t(i) >= totalPositions_)
            fail("vertex index " + std::to_string(v) + " out of range (" +
                 std::to_string(totalPositions_) + " vertices)");
        out = uint32_t(i);
        return next;
    }

    const std::string& path_;
    Chunk& c_;
    TriangleMesh& mesh_;
    Vec3d origin_;
    uint64_t totalPositions_;
    bool useNormals_, useUvs_, useColours_;
};

// The first 'v' statement of the file in double: far meshes are stored relative to it
// (streamOrigin). Garbled numbers read as 0 here; the parse pass reports them. hasColour: the
// statement has six numbers (x y z r g b), so the file has vertex colours.
Vec3d firstPosition(const std::vector<Chunk>& chunks, bool& hasColour) {
    for (const Chunk& c : chunks) {
        if (c.positions == 0) continue;
        Chunk copy = c;
        Vec3d first(0.0);
        bool found = false;
        forEachLine(copy, [&](Statement st, const char* p, const char* end) {
            if (st != Statement::Position || found) return;
            found = true;
            for (int k = 0; k < 3; ++k) {
                p = skipBlanks(p, end);
                const char* e = tokenEnd(p, end);
                std::from_chars(p, e, first[k]);
                p = e;
            }
            int more = 0;
            for (p = skipBlanks(p, end); p < end; p = skipBlanks(tokenEnd(p, end), end)) ++more;
            hasColour = more == 3;
        });
        return first;
    }
    return Vec3d(0.0);
}

// One mesh per group, each with the vertex range its triangles use (in OBJ files a group's
// vertices are normally its own contiguous block). False when groups share so many vertices that
// the copies would exceed twice the file's vertex count: Assimp then splits them by reference.
bool splitIntoGroups(const TriangleMesh& all,
                     const std::vector<std::pair<uint64_t, std::string>>& groups,
                     uint64_t triangles, std::vector<TriangleMesh>& out) {
    out.resize(groups.size());
    std::vector<uint32_t> lo(groups.size()), hi(groups.size());
    auto range = [&](size_t g) {
        uint64_t end = g + 1 < groups.size() ? groups[g + 1].first : triangles;
        return std::make_pair(groups[g].first, end);
    };
    tbb::parallel_for(size_t(0), groups.size(), [&](size_t g) {
        auto [t0, t1] = range(g);
        auto [mn, mx] = std::minmax_element(all.indices.begin() + long(3 * t0),
                                            all.indices.begin() + long(3 * t1));
        lo[g] = *mn, hi[g] = *mx;
    });
    uint64_t copied = 0;
    for (size_t g = 0; g < groups.size(); ++g) copied += uint64_t(hi[g] - lo[g]) + 1;
    if (copied > 2 * all.vertexCount() + 1024) return false;
    tbb::parallel_for(size_t(0), groups.size(), [&](size_t g) {
        auto [t0, t1] = range(g);
        TriangleMesh& m = out[g];
        m.name = groups[g].second;
        auto slice = [&](const std::vector<float>& from, size_t width) {
            return std::vector<float>(from.begin() + long(width * lo[g]),
                                      from.begin() + long(width * (size_t(hi[g]) + 1)));
        };
        m.positions = slice(all.positions, 3);
        m.positions.reserve(m.positions.size() + 1);
        if (!all.normals.empty()) m.normals = slice(all.normals, 3);
        if (!all.uvs.empty()) m.uvs = slice(all.uvs, 2);
        if (!all.colors.empty()) m.colors = slice(all.colors, 3);
        m.indices.assign(all.indices.begin() + long(3 * t0), all.indices.begin() + long(3 * t1));
        for (uint32_t& i : m.indices) i -= lo[g];
    });
    return true;
}

}  // namespace

void checkObjIndices(const std::string& path) {
    MappedFile file(path);
    Chunk all;
    all.begin = file.data(), all.end = file.data() + file.size();
    Chunk counted = all;
    countChunk(counted);  // the file's totals: positive indices may refer forward
    const uint64_t totals[3] = {counted.positions, counted.uvs, counted.normals};
    static constexpr const char* kKinds[3] = {"vertex", "texture coordinate", "normal"};
    static constexpr const char* kStatements[3] = {"'v' vertices", "'vt' texture coordinates",
                                                   "'vn' normals"};
    uint64_t defined[3] = {0, 0, 0}, line = 0;
    const char* p = all.begin;
    auto fail = [&](const std::string& what) {
        throw SceneError(path, "line " + std::to_string(line) + ": " + what);
    };
    while (p < all.end) {
        const char* nl = static_cast<const char*>(std::memchr(p, '\n', size_t(all.end - p)));
        const char* lineEnd = nl ? nl : all.end;
        const char* hash = static_cast<const char*>(std::memchr(p, '#', size_t(lineEnd - p)));
        const char* end = hash ? hash : lineEnd;
        ++line;
        const char* s = skipBlanks(p, end);
        const char* k = tokenEnd(s, end);
        std::string_view key(s, size_t(k - s));
        p = lineEnd + 1;
        if (key == "v") ++defined[0];
        if (key == "vt") ++defined[1];
        if (key == "vn") ++defined[2];
        if (key != "f" && key != "l" && key != "p") continue;
        for (const char* t = skipBlanks(k, end); t < end; t = skipBlanks(t, end)) {
            const char* e = tokenEnd(t, end);
            for (int kind = 0; kind < 3 && t < e; ++kind) {
                const char* slash = static_cast<const char*>(std::memchr(t, '/', size_t(e - t)));
                const char* partEnd = slash ? slash : e;
                if (partEnd > t) {
                    int64_t v = 0;
                    auto [next, ec] = std::from_chars(t, partEnd, v);
                    if (ec != std::errc() || next != partEnd)
                        fail("bad " + std::string(kKinds[kind]) + " index '" +
                             std::string(t, size_t(partEnd - t)) + "'");
                    uint64_t count = v < 0 ? defined[kind] : totals[kind];
                    if (v == 0 || (v > 0 && uint64_t(v) > count) || (v < 0 && v < -int64_t(count)))
                        fail(std::string(kKinds[kind]) + " index " + std::to_string(v) +
                             " out of range (" + std::to_string(count) + " " + kStatements[kind] +
                             (v < 0 ? " before it)" : " in the file)"));
                } else if (kind == 0) {
                    fail("a corner without a vertex index ('" + std::string(t, size_t(e - t)) +
                         "')");
                }
                t = slash ? slash + 1 : e;
            }
            t = e;
        }
    }
}

bool readObj(const std::string& path, Scene& scene) {
    MappedFile file(path);
    const char* data = file.data();
    const char* end = data + file.size();
    std::vector<Chunk> chunks;
    for (const char* p = data; p < end;) {
        const char* cut = p + std::min(kChunkBytes, size_t(end - p));
        if (cut < end) {
            const char* nl = static_cast<const char*>(std::memchr(cut, '\n', size_t(end - cut)));
            cut = nl ? nl + 1 : end;
        }
        chunks.emplace_back();
        chunks.back().begin = p, chunks.back().end = cut;
        p = cut;
    }
    tbb::parallel_for(size_t(0), chunks.size(), [&](size_t i) { countChunk(chunks[i]); });

    Chunk total;
    for (Chunk& c : chunks) {
        if (c.unsupported) return false;
        c.lineBase = total.lines, c.positionBase = total.positions, c.normalBase = total.normals;
        c.uvBase = total.uvs, c.triangleBase = total.triangles;
        total.lines += c.lines, total.positions += c.positions, total.normals += c.normals;
        total.uvs += c.uvs, total.triangles += c.triangles, total.corners += c.corners;
        total.cornersWithUv += c.cornersWithUv, total.cornersWithNormal += c.cornersWithNormal;
    }
    // Attributes are kept when every corner names one; a mix goes to Assimp.
    bool useNormals = total.corners > 0 && total.cornersWithNormal == total.corners;
    bool useUvs = total.corners > 0 && total.cornersWithUv == total.corners;
    if ((total.cornersWithNormal > 0 && !useNormals) || (total.cornersWithUv > 0 && !useUvs))
        return false;
    if (total.positions == 0) throw SceneError(path, "OBJ has no vertices ('v' lines)");
    if (total.positions >= UINT32_MAX || total.triangles >= UINT32_MAX / 3)
        throw SceneError(path, "more than 4 billion vertices or 1.4 billion triangles in one mesh");
    checkMemoryFor(path, total.positions, total.triangles);
    if (total.triangles >= 10'000'000)
        logInfo("loading {}: {} vertices, {} triangles", path, total.positions, total.triangles);

    // Normal and uv arrays are indexed like positions: only valid when the counts agree.
    if ((useNormals && total.normals != total.positions) ||
        (useUvs && total.uvs != total.positions))
        return false;
    TriangleMesh mesh;
    mesh.name = "obj";
    mesh.positions.reserve(3 * total.positions + 1);  // + Embree's padding float, no regrowth
    mesh.positions.resize(3 * total.positions);
    mesh.indices.resize(3 * total.triangles);
    if (useNormals) mesh.normals.resize(3 * total.positions);
    if (useUvs) mesh.uvs.resize(2 * total.positions);
    std::atomic<bool> sameIndices{true};
    bool useColours = false;
    Vec3d origin = streamOrigin(firstPosition(chunks, useColours));
    if (useColours) mesh.colors.resize(3 * total.positions);
    tbb::parallel_for(size_t(0), chunks.size(), [&](size_t i) {
        ChunkParser parser(path, chunks[i], mesh, total.positions, useNormals, useUvs, origin,
                           useColours);
        if (!parser.parse()) sameIndices = false;
    });
    if (!sameIndices) return false;

    // Groups with triangles, in file order: [first triangle, name].
    std::vector<std::pair<uint64_t, std::string>> groups = {{0, "defaultobject"}};
    for (const Chunk& c : chunks)
        for (const auto& [tri, name] : c.groups) groups.emplace_back(c.triangleBase + tri, name);
    std::vector<std::pair<uint64_t, std::string>> nonEmpty;
    for (size_t g = 0; g < groups.size(); ++g) {
        uint64_t next = g + 1 < groups.size() ? groups[g + 1].first : total.triangles;
        if (next > groups[g].first) nonEmpty.push_back(groups[g]);
    }
    std::vector<TriangleMesh> meshes;
    if (nonEmpty.size() <= 1) {
        if (!nonEmpty.empty()) mesh.name = nonEmpty[0].second;
        meshes.push_back(std::move(mesh));
    } else if (!splitIntoGroups(mesh, nonEmpty, total.triangles, meshes)) {
        return false;
    }
    // Assimp's default for an OBJ without materials, so both readers render a file alike.
    Material m{"DefaultMaterial"};
    m.albedo = Color(0.6f);
    for (TriangleMesh& part : meshes) {
        part.finalizePadding();
        part.materialIds = {uint32_t(scene.materials.size())};
        appendMesh(scene, std::move(part), origin);
    }
    scene.materials.push_back(m);
    return true;
}

}  // namespace kiln
