// The .kiln scene description: XML read with pugixml. Documented in docs/kiln-scene.md.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <pugixml.hpp>
#include <set>

#include "renderer/core/memory.h"
#include "scene/importers.h"
#include "scene/material_kinds.h"
#include "scene/mesh_maps.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

std::vector<double> numbers(const std::string& file, pugi::xml_node node, const char* attr,
                            size_t n) {
    std::string text = node.attribute(attr).as_string();
    std::vector<double> v;
    const char* p = text.c_str();
    while (*p) {
        char* end = nullptr;
        double x = std::strtod(p, &end);
        if (end == p) {
            while (*p == ' ') ++p;
            if (*p)
                throw SceneError(file, std::string("<") + node.name() + "> " + attr +
                                           ": garbled number '" + text + "'");
            break;
        }
        if (!std::isfinite(x))
            throw SceneError(file,
                             std::string("<") + node.name() + "> " + attr + ": non-finite number");
        v.push_back(x);
        p = end;
    }
    if (v.size() != n)
        throw SceneError(file, std::string("<") + node.name() + "> " + attr + " needs " +
                                   std::to_string(n) + " numbers, has " + std::to_string(v.size()));
    return v;
}

Vec3d vec3(const std::string& file, pugi::xml_node node, const char* attr) {
    auto v = numbers(file, node, attr, 3);
    return Vec3d(v[0], v[1], v[2]);
}

// Every attribute and child element of `node` must be one kiln reads: a typo is an error, not a
// silently ignored setting.
void checkKnown(const std::string& file, pugi::xml_node node,
                std::initializer_list<std::string_view> attributes,
                std::initializer_list<std::string_view> children = {}) {
    for (pugi::xml_attribute a : node.attributes())
        if (std::find(attributes.begin(), attributes.end(), a.name()) == attributes.end())
            throw SceneError(file, std::string("<") + node.name() + "> has unknown attribute '" +
                                       a.name() + "'");
    for (pugi::xml_node c : node.children())
        if (c.type() == pugi::node_element &&
            std::find(children.begin(), children.end(), c.name()) == children.end())
            throw SceneError(
                file, std::string("<") + node.name() + "> has unknown element <" + c.name() + ">");
}

// The transform of a <mesh> or <instances> element: <fit center size> scales the mesh uniformly so
// its largest side is `size` and puts its bounds' bottom centre at `center`; or translate / scale /
// matrix.
Mat4 placement(const std::string& file, pugi::xml_node node, const Bounds3T<double>& bounds) {
    Mat4 m;
    int ways = bool(node.child("fit")) + bool(node.child("matrix")) +
               (node.attribute("scale") || node.attribute("translate"));
    if (ways > 1)
        throw SceneError(file, std::string("<") + node.name() +
                                   "> has more than one of <fit>, <matrix> and scale/translate");
    if (pugi::xml_node fit = node.child("fit")) {
        checkKnown(file, fit, {"center", "size"});
        Vec3d c = vec3(file, fit, "center");
        double size = numbers(file, fit, "size", 1)[0];
        double extent = maxComponent(bounds.diagonal());
        if (!(size > 0) || !(extent > 0))
            throw SceneError(file, "<fit> needs a positive size and a mesh with extent");
        double s = size / extent;
        Vec3d mid = (bounds.lo + bounds.hi) * 0.5, bottom(mid.x, bounds.lo.y, mid.z);
        m.m[0][0] = m.m[1][1] = m.m[2][2] = s;
        for (int r = 0; r < 3; ++r) m.m[r][3] = c[r] - s * bottom[r];
        return m;
    }
    if (pugi::xml_node mat = node.child("matrix")) {
        checkKnown(file, mat, {"values"});
        auto v = numbers(file, mat, "values", 16);
        for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v[size_t(i)];
        return m;
    }
    if (node.attribute("scale"))
        m.m[0][0] = m.m[1][1] = m.m[2][2] = numbers(file, node, "scale", 1)[0];
    if (node.attribute("translate")) {
        Vec3d t = vec3(file, node, "translate");
        for (int r = 0; r < 3; ++r) m.m[r][3] = t[r];
    }
    return m;
}

// World bounds (double) of a part's meshes.
Bounds3T<double> meshBounds(const Scene& s) {
    Bounds3T<double> b;
    for (const TriangleMesh& m : s.meshes)
        for (size_t v = 0; v < m.vertexCount(); ++v) b.extend(s.world(m.vertex(uint32_t(v))));
    return b;
}

// xf applied to a part's stored coordinates: world = xf * (stored + part origin).
Mat4 fromStored(const Mat4& xf, const Vec3d& origin) {
    Mat4 t;
    for (int r = 0; r < 3; ++r) t.m[r][3] = origin[r];
    return xf * t;
}

// Appends src's materials and geometry; meshes are baked with xf unless asPrototype (then placed by
// `placements`, world transforms of the prototype's stored coordinates); material `override` (if
// >= 0) replaces every material of src. Positions go world = xf * (stored + src.origin) and back to
// dst's origin in double.
void merge(Scene& dst, Scene& src, const Mat4& xf, int override, bool asPrototype,
           const std::vector<Mat4>& placements) {
    uint32_t base = uint32_t(dst.materials.size());
    // The part's textures come along, their indices moved past dst's.
    int textureBase = int(dst.textureSources.size());
    dst.textureSources.insert(dst.textureSources.end(), src.textureSources.begin(),
                              src.textureSources.end());
    for (Material& m : src.materials)
        for (int* id : textureIds(m))
            if (*id >= 0) *id += textureBase;
    dst.materials.insert(dst.materials.end(), src.materials.begin(), src.materials.end());
    // An included .kiln file's media come along, the interiors naming them moved past dst's.
    const int mediumBase = int(dst.media.size());
    dst.media.insert(dst.media.end(), src.media.begin(), src.media.end());
    for (TriangleMesh& m : src.meshes)
        if (m.interior >= 0) m.interior += mediumBase;
    std::vector<bool> proto = src.prototypeMask();
    uint32_t meshBase = uint32_t(dst.meshes.size());
    Mat4 toWorld = fromStored(xf, src.origin);
    Bounds3T<double> placed;  // world bounds of what this part adds, for dst's origin
    Bounds3 local = src.storedBounds();
    for (const Mat4& p : asPrototype ? placements : std::vector<Mat4>{xf})
        for (int c = 0; !local.empty() && c < 8; ++c)
            placed.extend(fromStored(p, src.origin)
                              .point(Vec3d((c & 1) ? local.hi.x : local.lo.x,
                                           (c & 2) ? local.hi.y : local.lo.y,
                                           (c & 4) ? local.hi.z : local.lo.z)));
    Vec3d origin = adoptOrigin(dst, originFor(placed));
    Mat4 toStored;
    for (int r = 0; r < 3; ++r) toStored.m[r][3] = -origin[r];
    Mat4 bake = toStored * toWorld;  // src stored -> dst stored, one double transform
    bool flip = xf.determinant3() < 0;
    Mat4 inverse = xf.inverse();  // once: normals transform by its transpose
    for (size_t i = 0; i < src.meshes.size(); ++i) {
        TriangleMesh m = std::move(src.meshes[i]);
        for (uint32_t& id : m.materialIds) id = override >= 0 ? uint32_t(override) : id + base;
        if (!asPrototype && !proto[i]) {
            for (size_t v = 0; v < m.vertexCount(); ++v) {
                Vec3d p = bake.point(Vec3d(m.vertex(uint32_t(v))));
                for (int k = 0; k < 3; ++k) m.positions[3 * v + size_t(k)] = float(p[k]);
            }
            for (size_t v = 0; v + 2 < m.normals.size(); v += 3) {
                Vec3 n = normalize(transformNormal(
                    inverse, Vec3(m.normals[v], m.normals[v + 1], m.normals[v + 2])));
                m.normals[v] = n.x, m.normals[v + 1] = n.y, m.normals[v + 2] = n.z;
            }
            for (size_t v = 0; v + 3 < m.tangents.size(); v += 4) {
                Vec3 t =
                    normalize(xf.vector(Vec3(m.tangents[v], m.tangents[v + 1], m.tangents[v + 2])));
                m.tangents[v] = t.x, m.tangents[v + 1] = t.y, m.tangents[v + 2] = t.z;
                if (flip) m.tangents[v + 3] = -m.tangents[v + 3];
            }
            if (flip)
                for (size_t t = 0; t < m.triangleCount(); ++t)
                    std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
        }
        dst.meshes.push_back(std::move(m));
    }
    for (Instance inst : src.instances)
        dst.instances.push_back(Instance::place(inst.mesh + meshBase, bake * inst.objectToWorld));
    if (asPrototype)
        for (size_t i = 0; i < src.meshes.size(); ++i)
            if (!proto[i])
                for (const Mat4& p : placements)
                    dst.instances.push_back(Instance::place(meshBase + uint32_t(i),
                                                            toStored * fromStored(p, src.origin)));
    for (Sphere s : src.spheres) {
        s.center = Vec3(bake.point(Vec3d(s.center)));
        s.material = override >= 0 ? uint32_t(override) : s.material + base;
        s.radius *= float(std::cbrt(std::abs(xf.determinant3())));
        dst.spheres.push_back(s);
    }
    for (Light l : src.lights) {
        l.position = Vec3(bake.point(Vec3d(l.position)));
        l.dimX = xf.vector(l.dimX), l.dimY = xf.vector(l.dimY);
        if (l.kind != LightKind::Ambient && length(l.direction) > 0)
            l.direction = normalize(xf.vector(l.direction));
        dst.lights.push_back(l);
    }
    if (src.hasFileCamera && !dst.hasFileCamera) {
        dst.camera = src.camera;
        dst.camera.position = Vec3(bake.point(Vec3d(src.camera.position)));
        dst.hasFileCamera = true;
    }
    dst.warnings.insert(dst.warnings.end(), src.warnings.begin(), src.warnings.end());
}

// The texture an attribute names (a path relative to the .kiln file) as a source of the scene, or
// -1 when the attribute is absent.
int textureAttribute(const std::string& file, pugi::xml_node n, const char* attr,
                     TextureEncoding encoding, Scene& scene) {
    pugi::xml_attribute tex = n.attribute(attr);
    if (!tex) return -1;
    fs::path p = fs::path(file).parent_path() / tex.as_string();
    if (std::error_code ec; !fs::is_regular_file(p, ec))
        throw SceneError(file, "<material> " + std::string(attr) + " " + p.string() + " not found");
    TextureSource source;
    source.name = p.lexically_normal().string();
    source.encoding = encoding;
    scene.textureSources.push_back(std::move(source));
    return int(scene.textureSources.size()) - 1;
}

// One parameter of the kind (material_kinds.h): absent, the kind's default unless required.
void readParam(const std::string& file, pugi::xml_node n, const MaterialParam& p, Material& m) {
    if (!n.attribute(p.name) && !p.requiredInKiln) return;
    if (p.colour) {
        m.*p.colour = Color(vec3(file, n, p.name));
        return;
    }
    float v = float(numbers(file, n, p.name, 1)[0]);
    if (!inRange(p.range, v))
        throw SceneError(file,
                         "<material> " + std::string(p.name) + " must be " + rangeText(p.range));
    m.*p.scalar = v;
}

// A principled material's textures (glTF metallic-roughness), paths relative to the .kiln file.
void readPrincipledTextures(const std::string& file, pugi::xml_node n, Material& m, Scene& scene) {
    m.albedoTexture =
        textureAttribute(file, n, "base-color-texture", TextureEncoding::Color, scene);
    // glTF's layout: B metallic, G roughness, multiplying the factors.
    int mr = textureAttribute(file, n, "metallic-roughness-texture", TextureEncoding::Data, scene);
    m.maps.metallicTexture = m.maps.roughnessTexture = mr;
    m.maps.metallicChannel = 2, m.maps.roughnessChannel = 1;
    // glTF's clearcoatTexture: R multiplies the clear coat's weight.
    m.maps.clearcoatTexture =
        textureAttribute(file, n, "clearcoat-texture", TextureEncoding::Data, scene);
    m.maps.clearcoatChannel = 0;
    // glTF's clearcoatRoughnessTexture: G multiplies the coat's roughness.
    m.maps.clearcoatRoughnessTexture =
        textureAttribute(file, n, "clearcoat-roughness-texture", TextureEncoding::Data, scene);
    m.maps.clearcoatRoughnessChannel = 1;
    // glTF's transmissionTexture R, sheenColorTexture RGB (colour), sheenRoughnessTexture A.
    m.maps.transmissionTexture =
        textureAttribute(file, n, "transmission-texture", TextureEncoding::Data, scene);
    m.maps.transmissionChannel = 0;
    m.maps.sheenColorTexture =
        textureAttribute(file, n, "sheen-color-texture", TextureEncoding::Color, scene);
    m.maps.sheenRoughnessTexture =
        textureAttribute(file, n, "sheen-roughness-texture", TextureEncoding::Data, scene);
    m.maps.sheenRoughnessChannel = 3;
}

// Every attribute must be one this kind reads (its row's parameters): a typo, or a parameter of
// another kind, is an error rather than a silently ignored setting.
void checkMaterialAttributes(const std::string& file, pugi::xml_node n,
                             const MaterialKindSpec& spec) {
    for (pugi::xml_attribute a : n.attributes()) {
        std::string_view name = a.name();
        bool known = name == "name" || name == "kind" || (name == "emission" && spec.addsEmission);
        for (const MaterialParam& p : spec.params) known |= name == p.name;
        if (spec.kind == MaterialKind::Principled)
            known |= name == "base-color-texture" || name == "metallic-roughness-texture" ||
                     name == "clearcoat-texture" || name == "clearcoat-roughness-texture" ||
                     name == "transmission-texture" || name == "sheen-color-texture" ||
                     name == "sheen-roughness-texture";
        if (!known)
            throw SceneError(file, "<material> has unknown attribute '" + std::string(name) +
                                       "' for kind " + spec.name);
    }
}

Material parseMaterial(const std::string& file, pugi::xml_node n, Scene& scene) {
    Material m;
    m.name = n.attribute("name").as_string();
    std::string kind = n.attribute("kind").as_string("lambertian");
    const MaterialKindSpec* spec = findMaterialKind(kind);
    if (!spec || !spec->inKiln)
        throw SceneError(
            file, "unknown material kind '" + kind + "' (" +
                      materialKindNames([](const MaterialKindSpec& s) { return s.inKiln; }) + ")");
    m.kind = spec->kind;
    checkMaterialAttributes(file, n, *spec);
    if (spec->kilnDefaults) spec->kilnDefaults(m);
    for (const MaterialParam& p : spec->params) readParam(file, n, p, m);
    if (m.kind == MaterialKind::Principled) readPrincipledTextures(file, n, m, scene);
    // Emission is added to what the surface reflects (an emitting mesh is also a light).
    if (n.attribute("emission")) {
        if (!spec->addsEmission)
            throw SceneError(file, "<material> emission needs kind " +
                                       materialKindNames([](const MaterialKindSpec& s) {
                                           return s.addsEmission;
                                       }));
        m.emission = max(Color(vec3(file, n, "emission")), Color(0.0f));
    }
    return m;
}

// <medium name kind="homogeneous" sigma-a="r g b" sigma-s="r g b" g="0">: the inside of the meshes
// that name it as their interior.
Medium parseMedium(const std::string& file, pugi::xml_node n) {
    checkKnown(file, n, {"name", "kind", "sigma-a", "sigma-s", "g"});
    Medium m;
    m.name = n.attribute("name").as_string();
    if (m.name.empty()) throw SceneError(file, "<medium> needs a name");
    std::string kind = n.attribute("kind").as_string("homogeneous");
    if (kind != "homogeneous")
        throw SceneError(file, "<medium> kind '" + kind + "' is not known (homogeneous)");
    auto coefficients = [&](const char* attr) {
        if (!n.attribute(attr)) return Color(0.0f);
        Color c(vec3(file, n, attr));
        if (std::min({c.x, c.y, c.z}) < 0)
            throw SceneError(file, "<medium> " + std::string(attr) + " must be >= 0");
        return c;
    };
    m.sigmaA = coefficients("sigma-a");
    m.sigmaS = coefficients("sigma-s");
    if (n.attribute("g")) m.g = float(numbers(file, n, "g", 1)[0]);
    if (!(m.g > -1 && m.g < 1)) throw SceneError(file, "<medium> g must be in (-1, 1)");
    return m;
}

// The .kiln files being read, outermost first: an include cycle or runaway nesting is an error,
// not a stack overflow.
thread_local std::vector<std::string> includeStack;
// True while an outermost .kiln read imports the parts of a tree it has checked whole.
thread_local bool includesChecked = false;
// The files that read checked, by canonical path and depth (the depth limit depends on it): a file
// included many times in a tree is checked once there.
thread_local std::set<std::pair<std::string, size_t>> checkedTrees;
constexpr size_t kMaxIncludeDepth = 16;

std::string canonicalName(const std::string& path) {
    std::error_code ec;
    return fs::weakly_canonical(path, ec).string();
}

// path's canonical name; an include of a file being read (a cycle) is refused.
std::string notBeingRead(const std::string& path) {
    std::string canonical = canonicalName(path);
    if (std::find(includeStack.begin(), includeStack.end(), canonical) != includeStack.end())
        throw SceneError(path, "includes itself (include cycle)");
    return canonical;
}

class IncludeGuard {
  public:
    explicit IncludeGuard(const std::string& path) {
        std::string canonical = notBeingRead(path);
        if (includeStack.size() >= kMaxIncludeDepth)
            throw SceneError(
                path, "includes nested deeper than " + std::to_string(kMaxIncludeDepth) + " files");
        includeStack.push_back(canonical);
    }
    ~IncludeGuard() { includeStack.pop_back(); }
    IncludeGuard(const IncludeGuard&) = delete;
    IncludeGuard& operator=(const IncludeGuard&) = delete;
};

// Instances of a grid: positive whole counts whose product fits in memory, checked before any
// placement is made.
std::array<int, 3> gridCounts(const std::string& file, pugi::xml_node n) {
    auto grid = numbers(file, n, "grid", 3);
    double total = 1;
    std::array<int, 3> counts{};
    for (int i = 0; i < 3; ++i) {
        if (!(grid[i] >= 1) || grid[i] != std::floor(grid[i]) || grid[i] > 1e9)
            throw SceneError(file, "<instances> grid needs three whole numbers >= 1");
        counts[i] = int(grid[i]);
        total *= grid[i];
    }
    // Two transforms (object to world and back) per instance, as Scene::instances holds them,
    // plus the placement list and the accelerator's instance record.
    double need = total * (2 * sizeof(Instance) + 64);
    if (total > double(UINT32_MAX) || need > double(availableMemoryBytes())) {
        throw SceneError(
            file, fmt::format("<instances> grid of {:.0f} instances would need about {:.1f} GiB; "
                              "refusing",
                              total, need / double(1ull << 30)));
    }
    return counts;
}

// fov_axis: which image axis the fov spans. "narrow" (the default, as before the attribute) is the
// shorter side: the fov is given as both angles and the wider one fitted to the image.
Camera::FovAxis fovAxis(const std::string& path, pugi::xml_node n) {
    std::string axis = n.attribute("fov_axis").as_string("narrow");
    if (axis == "narrow") return Camera::FovAxis::Fit;
    if (axis == "horizontal") return Camera::FovAxis::Horizontal;
    if (axis == "vertical") return Camera::FovAxis::Vertical;
    if (axis == "diagonal") return Camera::FovAxis::Diagonal;
    throw SceneError(
        path,
        "<camera> fov_axis must be horizontal, vertical, diagonal or narrow, not '" + axis + "'");
}

// An <override spec="...">'s spec, as --material-override takes it: a file it names is relative to
// this .kiln, as every path in it.
std::string overrideSpec(const std::string& path, pugi::xml_node o) {
    std::string spec = o.attribute("spec").as_string();
    if (spec != "clay" && spec != kDiffuseOverride && spec.rfind("lambertian:", 0) != 0 &&
        fs::path(spec).is_relative())
        spec = (fs::path(path).parent_path() / spec).string();
    return spec;
}

// An <override> child's form (checkedPart): one of material="NAME" (a material of this file) or
// spec="...".
void checkOverrideForm(const std::string& path, pugi::xml_node n,
                       const std::map<std::string, uint32_t>& materials) {
    pugi::xml_node o = n.child("override");
    if (!o) return;
    checkKnown(path, o, {"material", "spec"});
    if (bool(o.attribute("material")) == bool(o.attribute("spec")))
        throw SceneError(path, "<override> needs one of material=\"NAME\" or spec=\"...\"");
    if (o.attribute("material") && !materials.count(o.attribute("material").as_string()))
        throw SceneError(path, std::string("<override> names unknown material '") +
                                   o.attribute("material").as_string() + "'");
    if (o.attribute("spec")) try {
            checkMaterialOverride(overrideSpec(path, o));
        } catch (const SceneError& e) {
            throw SceneError(path, std::string("<override> spec: ") + e.what());  // the .kiln
        }
}

// <override material="NAME"/> (a material of this file) or <override spec="clay"/> (as
// --material-override): replaces every material of the part that does not emit.
void applyOverride(const std::string& path, pugi::xml_node n,
                   const std::map<std::string, uint32_t>& materials, const Scene& scene,
                   Scene& part) {
    pugi::xml_node o = n.child("override");
    if (!o) return;
    if (o.attribute("spec")) {
        overrideMaterials(part, overrideSpec(path, o));
        return;
    }
    const uint32_t material = materials.at(o.attribute("material").as_string());  // checked
    overrideMaterials(part, scene.materials[material], scene.textureSources);
}

void readCamera(const std::string& path, pugi::xml_node n, Scene& scene) {
    checkKnown(path, n, {"position", "look-at", "up", "fov", "fov_axis"});
    Camera& c = scene.camera;
    Vec3d position = vec3(path, n, "position"), target = vec3(path, n, "look-at");
    Vec3d up = n.attribute("up") ? vec3(path, n, "up") : Vec3d(0, 1, 0);
    double fov = numbers(path, n, "fov", 1)[0];
    if (!(fov > 0 && fov < 180))
        throw SceneError(
            path, "<camera> fov must be between 0 and 180 degrees, not " + std::to_string(fov));
    if (!(length(target - position) > 0))
        throw SceneError(path, "<camera> position and look-at are the same point");
    if (!(length(cross(normalize(target - position), up)) > 1e-6))
        throw SceneError(path, "<camera> up is zero or parallel to the view direction");
    c.position = scene.stored(position);
    c.forward = Vec3(normalize(target - position));
    c.up = Vec3(normalize(up));
    c.hFovDeg = c.vFovDeg = float(fov);
    c.orthoHalfWidth = c.orthoHalfHeight = 0;  // perspective, whatever an included camera was
    c.fovAxis = fovAxis(path, n);
    c.fromFile = true;
    scene.hasFileCamera = true;
}

void readLight(const std::string& path, pugi::xml_node n, Scene& scene) {
    Light l;
    std::string kind = n.attribute("kind").as_string();
    if (kind == "directional") {
        checkKnown(path, n, {"kind", "radiance", "direction"});
        l.kind = LightKind::Directional;
        Vec3d d = vec3(path, n, "direction");
        if (!(length(d) > 0)) throw SceneError(path, "<light> direction is zero");
        l.direction = Vec3(normalize(d));
    } else if (kind == "point") {
        checkKnown(path, n, {"kind", "radiance", "position"});
        l.kind = LightKind::Point, l.position = scene.stored(vec3(path, n, "position"));
    } else if (kind == "ambient") {
        checkKnown(path, n, {"kind", "radiance"});
        l.kind = LightKind::Ambient, l.direction = Vec3(0, 1, 0);
    } else {
        throw SceneError(path, "unknown light kind '" + kind + "' (directional, point, ambient)");
    }
    l.radiance = Vec3(vec3(path, n, "radiance"));
    scene.lights.push_back(l);
}

// A <mesh>'s interior="NAME": the medium of this file filling it, or -1.
int interiorMedium(const std::string& path, pugi::xml_node n,
                   const std::map<std::string, int>& media) {
    if (!n.attribute("interior")) return -1;
    auto it = media.find(n.attribute("interior").as_string());
    if (it == media.end())
        throw SceneError(path, std::string("<mesh> interior names unknown medium '") +
                                   n.attribute("interior").as_string() + "'");
    return it->second;
}

// What an <include>, <mesh> or <instances> element asks for, checked before any file is read.
struct PartSpec {
    std::string tag, file, source;  // source: the file's path from the working directory
    int override = -1;              // a material of this file for every one of the part's
    int interior = -1;
    std::array<int, 3> grid{};
    double spacing = 0;
};

// The "<mesh file=...>: " prefix of a part's errors: the user edits the .kiln that asked for it.
SceneError partError(const std::string& path, const PartSpec& spec, const std::string& what) {
    return SceneError(path, "<" + spec.tag + " file=\"" + spec.file + "\">: " + what);
}

// Its attributes, names, grid, placement and override checked, and its file there: a mistake
// anywhere in the file is refused before a 100M-triangle part is imported.
PartSpec checkedPart(const std::string& path, pugi::xml_node n,
                     const std::map<std::string, uint32_t>& materials,
                     const std::map<std::string, int>& media, bool deep) {
    PartSpec spec;
    spec.tag = n.name();
    const std::string& tag = spec.tag;
    if (tag == "include")
        checkKnown(path, n, {"file"}, {"override"});
    else if (tag == "mesh")
        checkKnown(path, n, {"file", "material", "interior", "scale", "translate"},
                   {"fit", "matrix", "override"});
    else
        checkKnown(path, n, {"file", "material", "grid", "spacing", "scale", "translate"},
                   {"fit", "matrix", "override"});
    spec.file = n.attribute("file").as_string();
    if (spec.file.empty()) throw SceneError(path, "<" + tag + "> needs a file attribute");
    if (n.attribute("material")) {
        auto it = materials.find(n.attribute("material").as_string());
        if (it == materials.end())
            throw SceneError(path, "<" + tag + "> names unknown material '" +
                                       n.attribute("material").as_string() + "'");
        spec.override = int(it->second);
    }
    if (tag == "instances") {
        spec.grid = gridCounts(path, n);
        spec.spacing = numbers(path, n, "spacing", 1)[0];
    }
    spec.interior = interiorMedium(path, n, media);
    if (tag != "include") placement(path, n, Bounds3T<double>(Vec3d(0), Vec3d(1)));  // its syntax
    checkOverrideForm(path, n, materials);
    spec.source = (fs::path(path).parent_path() / spec.file).string();
    try {
        checkSceneFileOpens(spec.source);
        notBeingRead(spec.source);
        if (deep && lowerExtension(spec.source) == ".kiln") checkKilnScene(spec.source);
    } catch (const SceneError& e) {
        throw partError(path, spec, e.what());
    }
    return spec;
}

// <include>, <mesh> or <instances>: the referenced file read as a part, placed, merged.
void readPart(const std::string& path, pugi::xml_node n, const PartSpec& spec,
              const std::map<std::string, uint32_t>& materials, Scene& scene) {
    const std::string& tag = spec.tag;
    const int override = spec.override, interior = spec.interior;
    const std::array<int, 3>& grid = spec.grid;
    const double spacing = spec.spacing;
    Scene part;
    part.sourcePath = spec.source;
    try {
        importFile(part.sourcePath, part);
    } catch (const SceneError& e) {
        throw partError(path, spec, e.what());
    }
    applyOverride(path, n, materials, scene, part);  // (a spec's file joins part.inputFiles)
    scene.inputFiles.push_back(part.sourcePath);
    scene.inputFiles.insert(scene.inputFiles.end(), part.inputFiles.begin(), part.inputFiles.end());
    if (tag == "instances") {
        Mat4 fit = placement(path, n, meshBounds(part));
        std::vector<Mat4> placements;
        placements.reserve(size_t(grid[0]) * size_t(grid[1]) * size_t(grid[2]));
        for (int z = 0; z < grid[2]; ++z)
            for (int y = 0; y < grid[1]; ++y)
                for (int x = 0; x < grid[0]; ++x) {
                    Mat4 t = fit;
                    t.m[0][3] += x * spacing, t.m[1][3] += y * spacing, t.m[2][3] += z * spacing;
                    placements.push_back(t);
                }
        merge(scene, part, Mat4::identity(), override, true, placements);
    } else {
        Mat4 xf = tag == "mesh" ? placement(path, n, meshBounds(part)) : Mat4::identity();
        part.hasFileCamera = part.hasFileCamera && tag == "include";
        const size_t firstMesh = scene.meshes.size();
        merge(scene, part, xf, override, false, {});
        if (interior >= 0)
            for (size_t i = firstMesh; i < scene.meshes.size(); ++i)
                scene.meshes[i].interior = interior;
        scene.isCs184 = false;
    }
}

}  // namespace

namespace {

// A .kiln file parsed, its root element and the names of its children checked.
pugi::xml_node openKilnFile(const std::string& path, pugi::xml_document& doc) {
    pugi::xml_parse_result ok = doc.load_file(path.c_str());
    if (!ok)
        throw SceneError(path, std::string("malformed XML at byte ") + std::to_string(ok.offset) +
                                   ": " + ok.description());
    pugi::xml_node root = doc.child("kiln-scene");
    if (!root) throw SceneError(path, "not a kiln scene (no <kiln-scene> root element)");
    for (pugi::xml_node n : root.children()) {
        std::string tag = n.name();
        if (n.type() == pugi::node_element && tag != "material" && tag != "include" &&
            tag != "mesh" && tag != "instances" && tag != "camera" && tag != "light" &&
            tag != "medium")
            throw SceneError(path, "unknown element <" + tag + ">");
    }
    return root;
}

// The file's materials and media into scene, by name.
void readDefinitions(const std::string& path, pugi::xml_node root, Scene& scene,
                     std::map<std::string, uint32_t>& materials,
                     std::map<std::string, int>& media) {
    for (pugi::xml_node n : root.children("material")) {
        materials[n.attribute("name").as_string()] = uint32_t(scene.materials.size());
        scene.materials.push_back(parseMaterial(path, n, scene));
    }
    for (pugi::xml_node n : root.children("medium")) {
        Medium m = parseMedium(path, n);
        if (media.count(m.name)) throw SceneError(path, "<medium> " + m.name + " named twice");
        media[m.name] = int(scene.media.size());
        scene.media.push_back(std::move(m));
    }
}

// Every element after the definitions checked before the first part is imported: the parts
// (checkedPart, an included .kiln's whole tree too), the camera and lights on a scratch scene (they
// are stored against the origin the geometry fixes).
std::vector<std::pair<pugi::xml_node, PartSpec>> checkedElements(
    const std::string& path, pugi::xml_node root, const std::map<std::string, uint32_t>& materials,
    const std::map<std::string, int>& media, bool deep) {
    std::vector<std::pair<pugi::xml_node, PartSpec>> parts;
    for (pugi::xml_node n : root.children()) {
        std::string tag = n.name();
        if (tag == "include" || tag == "mesh" || tag == "instances")
            parts.emplace_back(n, checkedPart(path, n, materials, media, deep));
    }
    Scene scratch;
    for (pugi::xml_node n : root.children("camera")) readCamera(path, n, scratch);
    for (pugi::xml_node n : root.children("light")) readLight(path, n, scratch);
    return parts;
}

}  // namespace

void checkKilnScene(const std::string& path) {
    const std::pair<std::string, size_t> key{canonicalName(path), includeStack.size()};
    if (checkedTrees.count(key)) return;
    IncludeGuard guard(path);
    pugi::xml_document doc;
    pugi::xml_node root = openKilnFile(path, doc);
    Scene scratch;
    std::map<std::string, uint32_t> materials;
    std::map<std::string, int> media;
    readDefinitions(path, root, scratch, materials, media);
    checkedElements(path, root, materials, media, true);
    checkedTrees.insert(key);  // only once it passed (a file cannot reach itself at one depth)
}

bool kilnSceneLacksMaterial(const std::string& path, const std::string& name) {
    pugi::xml_document doc;
    pugi::xml_node root = openKilnFile(path, doc);
    for (pugi::xml_node n : root.children("material"))
        if (name.empty() || name == n.attribute("name").as_string()) return false;
    // A part's import may bring the material (a glTF's, a COLLADA file's): only importing it tells.
    for (const char* tag : {"include", "mesh", "instances"})
        if (root.child(tag)) return false;
    return true;
}

void readKilnScene(const std::string& path, Scene& scene) {
    IncludeGuard guard(path);
    pugi::xml_document doc;
    pugi::xml_node root = openKilnFile(path, doc);
    // Materials, then geometry, then camera and lights: the geometry fixes the scene's origin,
    // so positions given in the file are stored against it whatever the order of the elements.
    std::map<std::string, uint32_t> materials;
    std::map<std::string, int> media;
    readDefinitions(path, root, scene, materials, media);
    // The outermost read checks the whole tree of includes (checkKilnScene) once; the reads its
    // imports lead to check their own elements only (a tree re-checked at every level cost
    // depth x its size).
    const bool outermost = !includesChecked;
    if (outermost) checkedTrees.clear();
    auto parts = checkedElements(path, root, materials, media, outermost);
    includesChecked = true;
    struct Restore {
        bool was;
        ~Restore() { includesChecked = was; }
    } restore{!outermost};
    for (const auto& [n, spec] : parts) readPart(path, n, spec, materials, scene);
    for (pugi::xml_node n : root.children("camera")) readCamera(path, n, scene);
    for (pugi::xml_node n : root.children("light")) readLight(path, n, scene);
}

}  // namespace kiln
