#include "scene/scene_info.h"

#include <fmt/format.h>

#include <set>
#include <sstream>

#include "renderer/core/json.h"
#include "scene/material_kinds.h"

namespace kiln {
namespace {

std::string num(double v) { return fmt::format("{:.9g}", v); }
std::string vec(const Vec3d& v) { return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", v.x, v.y, v.z); }
std::string vec(const Vec3& v) { return vec(Vec3d(v)); }
// Floats as the nearest short decimal of the float (0.75, not 0.75000000298...).
Json jsonNumber(float v) { return std::stod(fmt::format("{}", v)); }
Json jsonVec(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }
Json jsonVec(const Vec3& v) {
    return Json::array({jsonNumber(v.x), jsonNumber(v.y), jsonNumber(v.z)});
}

}  // namespace

// Bounds in world coordinates (the scene is stored relative to Scene::origin).
Bounds3T<double> worldBoundsExact(const Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return {};
    return {scene.world(b.lo), scene.world(b.hi)};
}

Bounds3 worldBoundsOf(const Scene& scene) {
    Bounds3T<double> b = worldBoundsExact(scene);
    if (b.empty()) return {};
    return {Vec3(b.lo), Vec3(b.hi)};
}

SceneSummary summarize(const Scene& scene) {
    SceneSummary s;
    s.triangles = scene.instancedTriangles();
    s.uniqueTriangles = scene.uniqueTriangles();
    s.spheres = scene.spheres.size();
    s.meshes = scene.meshes.size();
    s.instances = scene.instances.size();
    std::set<uint32_t> used;
    for (const TriangleMesh& m : scene.meshes) {
        s.vertices += m.vertexCount();
        used.insert(m.materialIds.begin(), m.materialIds.end());
        s.geometryBytes += m.positions.size() * 4 + m.indices.size() * 4 + m.normals.size() * 4 +
                           m.uvs.size() * 4 + m.materialIds.size() * 4;
    }
    for (const Sphere& sp : scene.spheres) used.insert(sp.material);
    for (uint32_t id : used) ++s.materials[toString(scene.materials[id].kind)];
    for (const Light& l : scene.lights) ++s.lights[toString(l.kind)];
    return s;
}

std::string sceneInfoText(const Scene& scene) {
    SceneSummary s = summarize(scene);
    std::ostringstream os;
    Bounds3T<double> b = worldBoundsExact(scene);
    os << "scene       " << scene.sourcePath << "\n";
    os << "load        " << num(scene.loadSeconds) << " s\n";
    os << "geometry    " << s.triangles << " triangles (" << s.uniqueTriangles << " stored), "
       << s.vertices << " vertices, " << s.meshes << " meshes, " << s.instances << " instances, "
       << s.spheres << " spheres\n";
    os << "memory      " << s.geometryBytes << " bytes of geometry ("
       << num(s.uniqueTriangles ? double(s.geometryBytes) / double(s.uniqueTriangles) : 0.0)
       << " bytes/triangle)\n";
    if (!scene.duplicatesChecked)
        os << "duplicates  not checked (more than 20M triangles): ties between exact duplicates "
              "are not resolved\n";
    else if (scene.duplicateTriangles)
        os << "duplicates  " << scene.duplicateTriangles
           << " triangles repeat another; the lowest index wins\n";
    os << "bounds      " << vec(b.lo) << " .. " << vec(b.hi) << "\n";
    os << "materials\n";
    std::set<uint32_t> used;
    for (const TriangleMesh& m : scene.meshes)
        used.insert(m.materialIds.begin(), m.materialIds.end());
    for (const Sphere& sp : scene.spheres) used.insert(sp.material);
    for (uint32_t id : used) {
        const Material& m = scene.materials[id];
        os << "  " << toString(m.kind) << " '" << m.name << "'";
        os << " " << describeParams(m);
        if (specOf(m.kind).addsEmission && maxComponent(m.emission) > 0)
            os << " emission " << vec(m.emission);
        // Maps (scene/material_maps.h).
        if (m.maps.normalTexture >= 0) os << " normal-map scale " << num(m.maps.normalScale);
        if (m.maps.metallicTexture >= 0 || m.maps.roughnessTexture >= 0)
            os << " metallic-roughness-map";
        if (m.maps.emissionTexture >= 0) os << " emission-map";
        if (m.maps.clearcoatTexture >= 0 || m.maps.clearcoatRoughnessTexture >= 0)
            os << " clearcoat-map";
        if (m.maps.transmissionTexture >= 0) os << " transmission-map";
        if (m.maps.sheenColorTexture >= 0 || m.maps.sheenRoughnessTexture >= 0) os << " sheen-map";
        if (m.maps.hasAlpha())
            os << " alpha " << toString(m.maps.alphaMode) << " opacity " << num(m.maps.opacity)
               << (m.maps.alphaMode == AlphaMode::Mask ? " cutoff " + num(m.maps.alphaCutoff) : "")
               << (m.maps.opacityTexture >= 0 ? " textured" : "");
        os << "\n";
    }
    os << "lights\n";
    for (const Light& l : scene.lights) {
        os << "  " << toString(l.kind) << " '" << l.name << "' radiance " << vec(l.radiance);
        if (l.kind == LightKind::Area)
            os << " at " << vec(Vec3d(l.position) + scene.origin) << " facing " << vec(l.direction)
               << " size " << num(length(l.dimX)) << " x " << num(length(l.dimY));
        else if (l.kind == LightKind::Point || l.kind == LightKind::Spot)
            os << " at " << vec(Vec3d(l.position) + scene.origin);
        else if (l.kind == LightKind::Directional)
            os << " direction " << vec(l.direction);
        else if (l.kind == LightKind::Environment)
            os << " map " << l.environmentPath;
        else if (l.kind == LightKind::MeshEmitter)
            os << " mesh " << l.mesh;
        os << "\n";
    }
    const Camera& c = scene.camera;
    os << "camera      "
       << (scene.framedByCourseRule ? "file direction, CS184 framing"
           : scene.hasFileCamera    ? "file"
                                    : "default framing")
       << " at " << vec(Vec3d(c.position) + scene.origin) << " looking " << vec(c.forward);
    if (c.orthographic())
        os << " orthographic half width " << num(c.orthoHalfWidth) << " half height "
           << num(c.orthoHalfHeight) << "\n";
    else
        os << " hfov " << num(c.hFovDeg) << " vfov " << num(c.vFovDeg) << "\n";
    for (const std::string& w : scene.warnings) os << "warning     " << w << "\n";
    return os.str();
}

std::string sceneInfoJson(const Scene& scene) {
    SceneSummary s = summarize(scene);
    Bounds3T<double> b = worldBoundsExact(scene);
    const Camera& c = scene.camera;
    Json doc = {{"scene", scene.sourcePath},
                {"triangles", s.triangles},
                {"unique_triangles", s.uniqueTriangles},
                {"vertices", s.vertices},
                {"spheres", s.spheres},
                {"meshes", s.meshes},
                {"instances", s.instances},
                {"materials", s.materials},
                {"lights", s.lights},
                {"camera",
                 {{"position", jsonVec(Vec3d(c.position) + scene.origin)},
                  {"direction", jsonVec(c.forward)},
                  {"up", jsonVec(c.up)},
                  {"hfov", jsonNumber(c.hFovDeg)},
                  {"vfov", jsonNumber(c.vFovDeg)},
                  {"orthographic_half_width", jsonNumber(c.orthoHalfWidth)},
                  {"orthographic_half_height", jsonNumber(c.orthoHalfHeight)},
                  {"from_file", scene.hasFileCamera}}},
                {"bbox", {{"min", jsonVec(b.lo)}, {"max", jsonVec(b.hi)}}},
                {"geometry_bytes", s.geometryBytes},
                {"textures", scene.textureSources.size()},
                {"load_seconds", scene.loadSeconds},
                {"warnings", scene.warnings}};
    return jsonText(doc) + "\n";
}

}  // namespace kiln
