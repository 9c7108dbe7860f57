// The .kiln scene description: XML read with pugixml. Documented in docs/kiln-scene.md.
#include <cmath>
#include <filesystem>
#include <map>
#include <pugixml.hpp>

#include "scene/importers.h"
#include "scene/scene_error.h"

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

Vec3 vec3(const std::string& file, pugi::xml_node node, const char* attr) {
    auto v = numbers(file, node, attr, 3);
    return Vec3(float(v[0]), float(v[1]), float(v[2]));
}

// The transform of a <mesh> or <instances> element: <fit center size> scales the mesh uniformly so
// its largest side is `size` and puts its bounds' bottom centre at `center`; or translate / scale /
// matrix.
Mat4 placement(const std::string& file, pugi::xml_node node, const Bounds3& bounds) {
    Mat4 m;
    if (pugi::xml_node fit = node.child("fit")) {
        Vec3 c = vec3(file, fit, "center");
        double size = numbers(file, fit, "size", 1)[0];
        double extent = maxComponent(bounds.diagonal());
        if (!(size > 0) || !(extent > 0))
            throw SceneError(file, "<fit> needs a positive size and a mesh with extent");
        double s = size / extent;
        Vec3 bottom(bounds.centroid().x, bounds.lo.y, bounds.centroid().z);
        m.m[0][0] = m.m[1][1] = m.m[2][2] = s;
        for (int r = 0; r < 3; ++r) m.m[r][3] = double(c[r]) - s * double(bottom[r]);
        return m;
    }
    if (pugi::xml_node mat = node.child("matrix")) {
        auto v = numbers(file, mat, "values", 16);
        for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v[size_t(i)];
        return m;
    }
    if (node.attribute("scale"))
        m.m[0][0] = m.m[1][1] = m.m[2][2] = numbers(file, node, "scale", 1)[0];
    if (node.attribute("translate")) {
        Vec3 t = vec3(file, node, "translate");
        for (int r = 0; r < 3; ++r) m.m[r][3] = t[r];
    }
    return m;
}

Bounds3 meshBounds(const Scene& s) {
    Bounds3 b;
    for (const TriangleMesh& m : s.meshes)
        for (size_t v = 0; v < m.vertexCount(); ++v) b.extend(m.vertex(uint32_t(v)));
    return b;
}

// Appends src's materials and geometry; meshes are baked with xf unless asPrototype (then placed by
// `placements`); material `override` (if >= 0) replaces every material of src.
void merge(Scene& dst, Scene& src, const Mat4& xf, int override, bool asPrototype,
           const std::vector<Mat4>& placements) {
    uint32_t base = uint32_t(dst.materials.size());
    dst.materials.insert(dst.materials.end(), src.materials.begin(), src.materials.end());
    std::vector<bool> proto = src.prototypeMask();
    uint32_t meshBase = uint32_t(dst.meshes.size());
    bool flip = xf.determinant3() < 0;
    Mat4 inverse = xf.inverse();  // once: normals transform by its transpose
    for (size_t i = 0; i < src.meshes.size(); ++i) {
        TriangleMesh m = std::move(src.meshes[i]);
        for (uint32_t& id : m.materialIds) id = override >= 0 ? uint32_t(override) : id + base;
        if (!asPrototype && !proto[i]) {
            for (size_t v = 0; v < m.vertexCount(); ++v) {
                Vec3 p = xf.point(m.vertex(uint32_t(v)));
                m.positions[3 * v] = p.x, m.positions[3 * v + 1] = p.y,
                                m.positions[3 * v + 2] = p.z;
            }
            for (size_t v = 0; v + 2 < m.normals.size(); v += 3) {
                Vec3 n = normalize(transformNormal(
                    inverse, Vec3(m.normals[v], m.normals[v + 1], m.normals[v + 2])));
                m.normals[v] = n.x, m.normals[v + 1] = n.y, m.normals[v + 2] = n.z;
            }
            if (flip)
                for (size_t t = 0; t < m.triangleCount(); ++t)
                    std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
        }
        dst.meshes.push_back(std::move(m));
    }
    for (Instance inst : src.instances) {
        inst.mesh += meshBase;
        inst = Instance::place(inst.mesh, xf * inst.objectToWorld);
        dst.instances.push_back(inst);
    }
    if (asPrototype)
        for (size_t i = 0; i < src.meshes.size(); ++i)
            if (!proto[i])
                for (const Mat4& p : placements)
                    dst.instances.push_back(Instance::place(meshBase + uint32_t(i), p));
    for (Sphere s : src.spheres) {
        s.center = xf.point(s.center);
        s.material = override >= 0 ? uint32_t(override) : s.material + base;
        s.radius *= float(std::cbrt(std::abs(xf.determinant3())));
        dst.spheres.push_back(s);
    }
    for (Light l : src.lights) {
        l.position = xf.point(l.position);
        l.dimX = xf.vector(l.dimX), l.dimY = xf.vector(l.dimY);
        if (l.kind != LightKind::Ambient && length(l.direction) > 0)
            l.direction = normalize(xf.vector(l.direction));
        dst.lights.push_back(l);
    }
    if (src.hasFileCamera && !dst.hasFileCamera) {
        dst.camera = src.camera;
        dst.camera.position = xf.point(src.camera.position);
        dst.hasFileCamera = true;
    }
    dst.warnings.insert(dst.warnings.end(), src.warnings.begin(), src.warnings.end());
}

Material parseMaterial(const std::string& file, pugi::xml_node n) {
    Material m;
    m.name = n.attribute("name").as_string();
    std::string kind = n.attribute("kind").as_string("lambertian");
    if (kind == "lambertian") {
        if (n.attribute("albedo")) m.albedo = vec3(file, n, "albedo");
    } else if (kind == "mirror") {
        m.kind = MaterialKind::Mirror;
        if (n.attribute("reflectance")) m.reflectance = vec3(file, n, "reflectance");
    } else if (kind == "glass") {
        m.kind = MaterialKind::Glass;
        m.ior = float(numbers(file, n, "ior", 1)[0]);
    } else if (kind == "microfacet") {
        m.kind = MaterialKind::Microfacet;
        m.alpha = float(numbers(file, n, "alpha", 1)[0]);
        m.eta = vec3(file, n, "eta");
        m.k = vec3(file, n, "k");
    } else {
        throw SceneError(
            file, "unknown material kind '" + kind + "' (lambertian, mirror, glass, microfacet)");
    }
    return m;
}

}  // namespace

void readKilnScene(const std::string& path, Scene& scene) {
    pugi::xml_document doc;
    pugi::xml_parse_result ok = doc.load_file(path.c_str());
    if (!ok)
        throw SceneError(path, std::string("malformed XML at byte ") + std::to_string(ok.offset) +
                                   ": " + ok.description());
    pugi::xml_node root = doc.child("kiln-scene");
    if (!root) throw SceneError(path, "not a kiln scene (no <kiln-scene> root element)");
    fs::path dir = fs::path(path).parent_path();
    auto resolve = [&](pugi::xml_node n) {
        std::string f = n.attribute("file").as_string();
        if (f.empty())
            throw SceneError(path, std::string("<") + n.name() + "> needs a file attribute");
        return (dir / f).string();
    };
    std::map<std::string, uint32_t> materials;
    for (pugi::xml_node n : root.children()) {
        std::string tag = n.name();
        if (tag == "material") {
            materials[n.attribute("name").as_string()] = uint32_t(scene.materials.size());
            scene.materials.push_back(parseMaterial(path, n));
        } else if (tag == "include" || tag == "mesh" || tag == "instances") {
            Scene part;
            part.sourcePath = resolve(n);
            importFile(part.sourcePath, part);
            int override = -1;
            if (n.attribute("material")) {
                auto it = materials.find(n.attribute("material").as_string());
                if (it == materials.end())
                    throw SceneError(path, "<" + tag + "> names unknown material '" +
                                               n.attribute("material").as_string() + "'");
                override = int(it->second);
            }
            if (tag == "instances") {
                auto grid = numbers(path, n, "grid", 3);
                double spacing = numbers(path, n, "spacing", 1)[0];
                Mat4 fit = placement(path, n, meshBounds(part));
                std::vector<Mat4> placements;
                for (int z = 0; z < int(grid[2]); ++z)
                    for (int y = 0; y < int(grid[1]); ++y)
                        for (int x = 0; x < int(grid[0]); ++x) {
                            Mat4 t = fit;
                            t.m[0][3] += x * spacing, t.m[1][3] += y * spacing,
                                t.m[2][3] += z * spacing;
                            placements.push_back(t);
                        }
                if (placements.empty()) throw SceneError(path, "<instances> grid places nothing");
                merge(scene, part, Mat4::identity(), override, true, placements);
            } else {
                Mat4 xf = tag == "mesh" ? placement(path, n, meshBounds(part)) : Mat4::identity();
                part.hasFileCamera = part.hasFileCamera && tag == "include";
                merge(scene, part, xf, override, false, {});
                scene.isCs184 = false;
            }
        } else if (tag == "camera") {
            Camera& c = scene.camera;
            c.position = vec3(path, n, "position");
            c.forward = normalize(vec3(path, n, "look-at") - c.position);
            if (n.attribute("up")) c.up = normalize(vec3(path, n, "up"));
            c.hFovDeg = c.vFovDeg = float(numbers(path, n, "fov", 1)[0]);
            c.fromFile = true;
            scene.hasFileCamera = true;
        } else if (tag == "light") {
            Light l;
            std::string kind = n.attribute("kind").as_string();
            l.radiance = vec3(path, n, "radiance");
            if (kind == "directional")
                l.kind = LightKind::Directional,
                l.direction = normalize(vec3(path, n, "direction"));
            else if (kind == "point")
                l.kind = LightKind::Point, l.position = vec3(path, n, "position");
            else if (kind == "ambient")
                l.kind = LightKind::Ambient, l.direction = Vec3(0, 1, 0);
            else
                throw SceneError(path,
                                 "unknown light kind '" + kind + "' (directional, point, ambient)");
            scene.lights.push_back(l);
        } else if (n.type() == pugi::node_element) {
            throw SceneError(path, "unknown element <" + tag + ">");
        }
    }
}

}  // namespace kiln
