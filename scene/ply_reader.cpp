// A direct PLY reader: binary (both endians) and ASCII, vertex positions/normals/uvs, faces as
// polygon lists (fan-triangulated) and tristrips (-1 restarts, degenerate strip triangles dropped).

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "renderer/core/log.h"
#include "scene/importers.h"
#include "scene/mapped_file.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };

PlyType parseType(const std::string& s) {
    if (s == "char" || s == "int8") return PlyType::Int8;
    if (s == "uchar" || s == "uint8") return PlyType::UInt8;
    if (s == "short" || s == "int16") return PlyType::Int16;
    if (s == "ushort" || s == "uint16") return PlyType::UInt16;
    if (s == "int" || s == "int32") return PlyType::Int32;
    if (s == "uint" || s == "uint32") return PlyType::UInt32;
    if (s == "float" || s == "float32") return PlyType::Float32;
    if (s == "double" || s == "float64") return PlyType::Float64;
    return PlyType::Invalid;
}

size_t typeSize(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
        default:
            return 0;
    }
}

// A colour component as stored: integers are display codes (sRGB-encoded, as 8-bit images are),
// normalised to [0, 1] and decoded for the whole mesh at once (decodeSrgbTexels); floats are linear
// as written.
float storedColour(double value, PlyType type) {
    switch (type) {
        case PlyType::UInt8:
            return float(value / 255.0);
        case PlyType::UInt16:
            return float(value / 65535.0);
        case PlyType::Float32:
        case PlyType::Float64:
            return float(value);
        default:
            return std::clamp(float(value / 255.0), 0.0f, 1.0f);
    }
}

bool isDisplayCode(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

struct Property {
    std::string name;
    PlyType type = PlyType::Invalid;
    bool isList = false;
    PlyType countType = PlyType::Invalid;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

// What the header alone decides of the vertex element (there, with x, y and z, no more rows than
// the file can hold), refused before any row is read: an element of 100M rows may come first.
void checkVertexElement(const std::string& path, const std::vector<Element>& elements,
                        size_t fileBytes, Format format) {
    bool found = false;
    for (const Element& e : elements) {
        if (e.name != "vertex") continue;
        found = true;
        auto has = [&](const char* name) {
            return std::any_of(e.props.begin(), e.props.end(),
                               [&](const Property& p) { return p.name == name; });
        };
        if (!has("x") || !has("y") || !has("z"))
            throw SceneError(path, "PLY vertex element lacks x, y or z");
        if (e.count > (fileBytes / (format == Format::Ascii ? 6 : 12)) + 1)
            throw SceneError(path, "PLY header declares " + std::to_string(e.count) +
                                       " vertices, more than the file can hold");
    }
    if (!found) throw SceneError(path, "PLY has no vertex element");
}

// Reads values from the body, binary or ASCII, with bounds checks that name the file.
class Cursor {
  public:
    Cursor(const std::string& path, const char* p, const char* end, Format f)
        : path_(path), p_(p), end_(end), f_(f) {}

    double read(PlyType t) {
        if (f_ == Format::Ascii) {
            double v = readAscii();
            if (t != PlyType::Float32 && t != PlyType::Float64 && v != std::floor(v))
                throw SceneError(path_, "non-integer value " + std::to_string(v) +
                                            " for an integer PLY property");
            return v;
        }
        size_t n = typeSize(t);
        if (size_t(end_ - p_) < n)
            throw SceneError(path_, "file ends before the data its header declares");
        unsigned char b[8];
        std::memcpy(b, p_, n);
        p_ += n;
        if ((f_ == Format::BinaryBE) != (std::endian::native == std::endian::big))
            for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        switch (t) {
            case PlyType::Int8:
                return double(int8_t(b[0]));
            case PlyType::UInt8:
                return double(b[0]);
            case PlyType::Int16: {
                int16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyType::UInt16: {
                uint16_t v;
                std::memcpy(&v, b, 2);
                return v;
            }
            case PlyType::Int32: {
                int32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::UInt32: {
                uint32_t v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::Float32: {
                float v;
                std::memcpy(&v, b, 4);
                return v;
            }
            case PlyType::Float64: {
                double v;
                std::memcpy(&v, b, 8);
                return v;
            }
            default:
                return 0;
        }
    }
    // Reads past one value of a property, list or scalar.
    void skipProperty(const Property& p) {
        if (!p.isList) {
            read(p.type);
            return;
        }
        size_t n = listLength(p);
        for (size_t k = 0; k < n; ++k) read(p.type);
    }
    // A list's length: a non-negative integer.
    size_t listLength(const Property& p) {
        double n = read(p.countType);
        if (!(n >= 0) || n != std::floor(n))
            throw SceneError(
                path_, "PLY list length " + std::to_string(n) + " is not a non-negative integer");
        return size_t(n);
    }
    const char* position() const { return p_; }
    void skip(size_t n) {
        if (size_t(end_ - p_) < n)
            throw SceneError(path_, "file ends before the data its header declares");
        p_ += n;
    }

  private:
    double readAscii() {
        while (p_ < end_ && (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) ++p_;
        if (p_ >= end_) throw SceneError(path_, "file ends before the data its header declares");
        const char* tokenEnd = p_;
        while (tokenEnd < end_ && !std::isspace(static_cast<unsigned char>(*tokenEnd))) ++tokenEnd;
        double v = 0;
        auto [next, ec] = std::from_chars(p_, tokenEnd, v);
        if (ec != std::errc() || next != tokenEnd)
            throw SceneError(path_,
                             "garbled number '" +
                                 std::string(p_, size_t(std::min<ptrdiff_t>(tokenEnd - p_, 40))) +
                                 "' in PLY body");
        p_ = next;
        return v;
    }
    const std::string& path_;
    const char* p_;
    const char* end_;
    Format f_;
};

}  // namespace

void checkMemoryFor(const std::string& path, uint64_t vertices, uint64_t triangles) {
    // Scene model: 12 bytes per vertex position (+12 normals at most), 12 per triangle; Embree's
    // BVH measured 64 bytes per triangle on igea_subdiv1_1M (kiln info), 80 leaves room for the
    // build.
    uint64_t need = vertices * 24 + triangles * 12 + triangles * 80;
    uint64_t have = availableMemoryBytes();
    if (need > have) {
        throw SceneError(path, fmt::format("would need about {:.1f} GiB for {} vertices and {} "
                                           "faces (scene model and BVH), but only {:.1f} GiB of "
                                           "memory is available",
                                           double(need) / (1ull << 30), vertices, triangles,
                                           double(have) / (1ull << 30)));
    }
}

void readPly(const std::string& path, Scene& scene) {
    MappedFile file(path);
    const char* data = file.data();
    const char* end = data + file.size();
    if (file.size() < 4 || std::strncmp(data, "ply", 3) != 0)
        throw SceneError(path, "not a PLY file (no 'ply' magic)");
    const char* headerEnd = nullptr;
    for (const char* p = data; p + 10 <= end; ++p)
        if (std::strncmp(p, "end_header", 10) == 0) {
            headerEnd = p + 10;
            break;
        }
    if (!headerEnd) throw SceneError(path, "PLY header has no end_header");
    while (headerEnd < end && *headerEnd != '\n') ++headerEnd;
    if (headerEnd < end) ++headerEnd;

    std::istringstream header(std::string(data, headerEnd));
    std::string line;
    Format format = Format::Ascii;
    std::vector<Element> elements;
    bool haveFormat = false;
    while (std::getline(header, line)) {
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "format") {
            std::string f;
            ls >> f;
            if (f == "ascii")
                format = Format::Ascii;
            else if (f == "binary_little_endian")
                format = Format::BinaryLE;
            else if (f == "binary_big_endian")
                format = Format::BinaryBE;
            else
                throw SceneError(path, "unknown PLY format '" + f + "'");
            haveFormat = true;
        } else if (word == "element") {
            Element e;
            std::string count, extra;
            ls >> e.name >> count >> extra;
            auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
            if (e.name.empty() || count.empty() || ec != std::errc() ||
                end != count.data() + count.size() || !extra.empty())
                throw SceneError(path,
                                 "malformed PLY element line (needs a name and a "
                                 "non-negative whole count): '" +
                                     line + "'");
            elements.push_back(e);
        } else if (word == "property") {
            if (elements.empty()) throw SceneError(path, "PLY property before any element");
            Property p;
            std::string t;
            ls >> t;
            if (t == "list") {
                std::string ct, it;
                ls >> ct >> it >> p.name;
                p.isList = true;
                p.countType = parseType(ct);
                p.type = parseType(it);
            } else {
                p.type = parseType(t);
                ls >> p.name;
            }
            if (p.type == PlyType::Invalid || (p.isList && p.countType == PlyType::Invalid))
                throw SceneError(path, "unknown PLY property type in '" + line + "'");
            elements.back().props.push_back(p);
        }
    }
    if (!haveFormat) throw SceneError(path, "PLY header has no format line");

    // Refuse, before allocating anything, a file whose geometry and BVH would not fit in memory.
    uint64_t vertices = 0, faces = 0;
    for (const Element& e : elements) {
        if (e.name == "vertex") vertices += e.count;
        if (e.name == "face" || e.name == "tristrips") faces += e.count;
    }
    checkMemoryFor(path, vertices, faces);
    checkVertexElement(path, elements, file.size(), format);

    TriangleMesh mesh;
    mesh.name = "ply";
    size_t vertexCount = 0;
    Vec3d origin(0.0);
    Cursor cur(path, headerEnd, end, format);
    for (const Element& e : elements) {
        if (e.name == "vertex") {
            vertexCount = e.count;
            int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iu = -1, iv = -1;
            int ir = -1, ig = -1, ib = -1;
            for (size_t i = 0; i < e.props.size(); ++i) {
                const std::string& n = e.props[i].name;
                if (n == "x")
                    ix = int(i);
                else if (n == "y")
                    iy = int(i);
                else if (n == "z")
                    iz = int(i);
                else if (n == "nx")
                    inx = int(i);
                else if (n == "ny")
                    iny = int(i);
                else if (n == "nz")
                    inz = int(i);
                else if (n == "u" || n == "s" || n == "texture_u")
                    iu = int(i);
                else if (n == "v" || n == "t" || n == "texture_v")
                    iv = int(i);
                else if (n == "red" || n == "diffuse_red")
                    ir = int(i);
                else if (n == "green" || n == "diffuse_green")
                    ig = int(i);
                else if (n == "blue" || n == "diffuse_blue")
                    ib = int(i);
            }
            bool normals = inx >= 0 && iny >= 0 && inz >= 0, uvs = iu >= 0 && iv >= 0;
            bool colours = ir >= 0 && ig >= 0 && ib >= 0;
            mesh.positions.resize(3 * e.count + 1);
            if (normals) mesh.normals.resize(3 * e.count);
            if (uvs) mesh.uvs.resize(2 * e.count);
            if (colours) mesh.colors.resize(3 * e.count);
            // Fast path, the common binary layout: little-endian float x y z and nothing else.
            bool packedXyz = format == Format::BinaryLE &&
                             std::endian::native == std::endian::little && e.props.size() == 3 &&
                             ix == 0 && iy == 1 && iz == 2;
            for (const Property& p : e.props) packedXyz &= !p.isList && p.type == PlyType::Float32;
            if (packedXyz) {
                const char* src = cur.position();
                cur.skip(size_t(e.count) * 12);
                std::memcpy(mesh.positions.data(), src, size_t(e.count) * 12);
                continue;
            }
            std::vector<double> row(e.props.size());
            for (uint64_t v = 0; v < e.count; ++v) {
                for (size_t i = 0; i < e.props.size(); ++i) {
                    if (e.props[i].isList) {
                        cur.skipProperty(e.props[i]);
                        continue;
                    }
                    row[i] = cur.read(e.props[i].type);
                }
                if (v == 0) origin = streamOrigin(Vec3d(row[ix], row[iy], row[iz]));
                // Parsed in double, stored in float relative to the origin (far coordinates).
                mesh.positions[3 * v] = float(row[ix] - origin.x);
                mesh.positions[3 * v + 1] = float(row[iy] - origin.y);
                mesh.positions[3 * v + 2] = float(row[iz] - origin.z);
                if (normals) {
                    mesh.normals[3 * v] = float(row[inx]);
                    mesh.normals[3 * v + 1] = float(row[iny]);
                    mesh.normals[3 * v + 2] = float(row[inz]);
                }
                if (uvs) {
                    mesh.uvs[2 * v] = float(row[iu]);
                    mesh.uvs[2 * v + 1] = float(row[iv]);
                }
                if (colours) {
                    mesh.colors[3 * v] = storedColour(row[ir], e.props[size_t(ir)].type);
                    mesh.colors[3 * v + 1] = storedColour(row[ig], e.props[size_t(ig)].type);
                    mesh.colors[3 * v + 2] = storedColour(row[ib], e.props[size_t(ib)].type);
                }
            }
            if (colours && isDisplayCode(e.props[size_t(ir)].type)) {
                mesh.colorsInWorkingSpace = true;
                if (e.props[size_t(ir)].type == PlyType::UInt8) {  // exact codes: the table
                    const std::array<float, 256> table = srgb8Table();
                    for (float& c : mesh.colors) c = table[size_t(std::lround(c * 255.0f))];
                } else {
                    decodeSrgbTexels(mesh.colors.data(), size_t(e.count), 3);
                }
            }
        } else if (e.name == "face" || e.name == "tristrips") {
            bool strips = e.name == "tristrips";
            std::vector<uint32_t> poly;
            if (!strips) mesh.indices.reserve(mesh.indices.size() + 3 * e.count);
            // Fast path: binary little-endian faces of one uchar-counted int list, read as 13-byte
            // triangle records straight from the mapped file (other polygons still take the general
            // path below).
            bool packedFaces =
                !strips && format == Format::BinaryLE &&
                std::endian::native == std::endian::little && e.props.size() == 1 &&
                e.props[0].isList && e.props[0].countType == PlyType::UInt8 &&
                (e.props[0].type == PlyType::Int32 || e.props[0].type == PlyType::UInt32) &&
                (e.props[0].name == "vertex_indices" || e.props[0].name == "vertex_index");
            uint64_t f0 = 0;
            // Long loads say how far they are (every quarter), so a 100M-triangle file is not a
            // silent wait.
            bool report = e.count >= 10'000'000;
            uint64_t nextReport = e.count / 4;
            if (packedFaces) {
                for (; f0 < e.count; ++f0) {
                    if (report && f0 == nextReport) {
                        logInfo("loading {}: {}% of {} faces", path, int(100 * f0 / e.count),
                                e.count);
                        nextReport += e.count / 4;
                    }
                    const unsigned char* rec =
                        reinterpret_cast<const unsigned char*>(cur.position());
                    if (size_t(end - cur.position()) < 13 || rec[0] != 3)
                        break;  // not a triangle: general path
                    uint32_t idx[3];
                    std::memcpy(idx, rec + 1, 12);
                    for (uint32_t i : idx)
                        if (i >= vertexCount)
                            throw SceneError(path,
                                             "face " + std::to_string(f0) + " has vertex index " +
                                                 std::to_string(int32_t(i)) + " out of range (" +
                                                 std::to_string(vertexCount) + " vertices)");
                    mesh.indices.insert(mesh.indices.end(), idx, idx + 3);
                    cur.skip(13);
                }
            }
            for (uint64_t f = f0; f < e.count; ++f) {
                for (const Property& p : e.props) {
                    if (!p.isList) {
                        cur.read(p.type);
                        continue;
                    }
                    size_t n = cur.listLength(p);
                    bool isIndexList = p.name == "vertex_indices" || p.name == "vertex_index";
                    poly.clear();
                    for (size_t k = 0; k < n; ++k) {
                        double idx = cur.read(p.type);
                        if (!isIndexList) continue;
                        if (strips && idx < 0) {
                            poly.push_back(UINT32_MAX);  // strip restart
                            continue;
                        }
                        if (idx != std::floor(idx))
                            throw SceneError(path, "face " + std::to_string(f) +
                                                       " has a non-integer vertex index " +
                                                       std::to_string(idx));
                        if (idx < 0 || idx >= double(vertexCount))
                            throw SceneError(path,
                                             "face " + std::to_string(f) + " has vertex index " +
                                                 std::to_string(int64_t(idx)) + " out of range (" +
                                                 std::to_string(vertexCount) + " vertices)");
                        poly.push_back(uint32_t(idx));
                    }
                    if (!isIndexList) continue;
                    if (!strips) {
                        for (size_t k = 2; k < poly.size(); ++k)
                            mesh.indices.insert(mesh.indices.end(),
                                                {poly[0], poly[k - 1], poly[k]});
                        continue;
                    }
                    // Tristrip: alternate winding; drop restarts and degenerate (repeated-index)
                    // triangles.
                    size_t run = 0;
                    for (size_t k = 0; k < poly.size(); ++k) {
                        if (poly[k] == UINT32_MAX) {
                            run = 0;
                            continue;
                        }
                        if (++run < 3) continue;
                        uint32_t a = poly[k - 2], b = poly[k - 1], c = poly[k];
                        if (a == b || b == c || a == c) continue;
                        if (run % 2 == 1)
                            mesh.indices.insert(mesh.indices.end(), {a, b, c});
                        else
                            mesh.indices.insert(mesh.indices.end(), {b, a, c});
                    }
                }
            }
        } else {
            // Unknown element: skip its rows.
            for (uint64_t r = 0; r < e.count; ++r)
                for (const Property& p : e.props) cur.skipProperty(p);
        }
    }
    mesh.finalizePadding();
    mesh.materialIds = {uint32_t(scene.materials.size())};
    scene.materials.push_back(Material{"ply-default"});
    appendMesh(scene, std::move(mesh), origin);
}

}  // namespace kiln
