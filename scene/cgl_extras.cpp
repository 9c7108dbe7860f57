#include "scene/cgl_extras.h"

#include <cmath>
#include <cstdlib>
#include <pugixml.hpp>
#include <sstream>

#include "scene/material_kinds.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

// Strict number-list parser: garbled text or a wrong count is a SceneError naming the element.
std::vector<double> parseNumbers(const std::string& file, pugi::xml_node node, const char* what,
                                 const char* text = nullptr) {
    std::vector<double> values;
    if (!text) text = node.child_value();
    const char* p = text;
    while (*p) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
        if (!*p) break;
        char* end = nullptr;
        double v = std::strtod(p, &end);
        if (end == p)
            throw SceneError(file, std::string("garbled number in <") + what + ">: '" + text + "'");
        if (!std::isfinite(v))
            throw SceneError(file, std::string("non-finite number in <") + what + ">");
        values.push_back(v);
        p = end;
    }
    return values;
}

std::vector<double> expectNumbers(const std::string& file, pugi::xml_node node, const char* what,
                                  size_t n) {
    if (!node) throw SceneError(file, std::string("missing <") + what + ">");
    std::vector<double> v = parseNumbers(file, node, what);
    if (v.size() != n)
        throw SceneError(file, std::string("<") + what + "> needs " + std::to_string(n) +
                                   " numbers, has " + std::to_string(v.size()));
    return v;
}

Color expectColor(const std::string& file, pugi::xml_node parent, const char* child) {
    pugi::xml_node node = parent.child(child);
    if (!node)
        throw SceneError(file,
                         std::string("CGL <") + parent.name() + "> is missing <" + child + ">");
    std::vector<double> v = parseNumbers(file, node, child);
    // COLLADA colours may carry alpha; it is ignored, as the course program does.
    if (v.size() != 3 && v.size() != 4)
        throw SceneError(
            file, std::string("<") + child + "> needs 3 numbers, has " + std::to_string(v.size()));
    return Color(float(v[0]), float(v[1]), float(v[2]));
}

float expectScalar(const std::string& file, pugi::xml_node parent, const char* child) {
    pugi::xml_node node = parent.child(child);
    if (!node)
        throw SceneError(file,
                         std::string("CGL <") + parent.name() + "> is missing <" + child + ">");
    return float(expectNumbers(file, node, child, 1)[0]);
}

// The CGL technique (or the identical older CMU462 one) under an element's <extra>.
pugi::xml_node extraTechnique(pugi::xml_node owner) {
    for (pugi::xml_node extra : owner.children("extra"))
        for (pugi::xml_node tech : extra.children("technique")) {
            std::string profile = tech.attribute("profile").as_string();
            if (profile == "CGL" || profile == "CMU462") return tech;
        }
    return {};
}

std::string urlTarget(pugi::xml_attribute attr) {
    std::string s = attr.as_string();
    return (!s.empty() && s[0] == '#') ? s.substr(1) : s;
}

Mat4 matrixFromRowMajor(const std::vector<double>& v) {
    Mat4 m;
    for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v[i];
    return m;
}

class Parser {
  public:
    Parser(const std::string& file, pugi::xml_document& doc) : file_(file), doc_(doc) {}

    ColladaExtras run() {
        pugi::xml_node root = doc_.child("COLLADA");
        if (!root) throw SceneError(file_, "not a COLLADA document (no <COLLADA> root element)");
        std::string up = root.child("asset").child_value("up_axis");
        if (up.find("Z_UP") != std::string::npos) {
            out_.zUp = true;
            Mat4 fix;
            fix.m[0][0] = -1, fix.m[1][1] = 0, fix.m[1][2] = 1, fix.m[2][1] = 1, fix.m[2][2] = 0;
            out_.upAxisFix = fix;
        }
        if (pugi::xml_node unit = root.child("asset").child("unit"); unit.attribute("meter")) {
            std::vector<double> meter = parseNumbers(file_, pugi::xml_node(), "unit meter",
                                                     unit.attribute("meter").as_string());
            if (meter.size() != 1 || !(meter[0] > 0))
                throw SceneError(file_, "<unit meter> must be one positive number");
            out_.unitMeters = meter[0];
        }
        checkColladaGeometry(file_, root);
        // The course's light rule (colour as intensity, 1 / d^2) for the files it was made for:
        // those with CGL/CMU462 techniques, and the Z-up Blender exports of the CS184 library
        // (which carry none in meshedit/ and keenan/). Every other file: COLLADA's own model.
        std::string tool = root.child("asset").child("contributor").child_value("authoring_tool");
        courseLights_ = root.select_node(".//technique[@profile='CGL' or @profile='CMU462']") ||
                        (out_.zUp && tool.rfind("Blender", 0) == 0);
        for (pugi::xml_node lib : root.children()) index(lib);
        parseMaterials(root.child("library_materials"));
        pugi::xml_node visual = root.child("library_visual_scenes").child("visual_scene");
        std::string sceneUrl =
            urlTarget(root.child("scene").child("instance_visual_scene").attribute("url"));
        if (!sceneUrl.empty())
            for (pugi::xml_node vs : root.child("library_visual_scenes").children("visual_scene"))
                if (sceneUrl == vs.attribute("id").as_string()) visual = vs;
        Mat4 base = out_.upAxisFix;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) base.m[i][j] *= out_.unitMeters;
        for (pugi::xml_node node : visual.children("node")) walk(node, base);
        storeRelativeToOrigin();
        if (patched_) {
            std::ostringstream os;
            doc_.save(os, "", pugi::format_raw);
            out_.patchedXml = os.str();
        }
        return std::move(out_);
    }

  private:
    void index(pugi::xml_node lib) {
        for (pugi::xml_node child : lib.children()) {
            const char* id = child.attribute("id").as_string();
            if (*id) byId_[id] = child;
        }
    }

    pugi::xml_node find(const std::string& id) const {
        auto it = byId_.find(id);
        return it == byId_.end() ? pugi::xml_node() : it->second;
    }

    Material parseEffect(pugi::xml_node effect, const std::string& name) {
        Material m;
        m.name = name;
        // No CGL child: Lambertian with the Phong (or Lambert/Blinn) diffuse colour.
        pugi::xml_node common = effect.child("profile_COMMON").child("technique");
        for (const char* shader : {"phong", "lambert", "blinn"}) {
            pugi::xml_node diffuse = common.child(shader).child("diffuse").child("color");
            if (diffuse) {
                m.albedo = expectColor(file_, common.child(shader).child("diffuse"), "color");
                break;
            }
        }
        // The standard <emission><color>: under the CGL rules an emitting material is a light
        // (a CGL <emission> extra, below, states its radiance instead).
        for (const char* shader : {"phong", "lambert", "blinn", "constant"}) {
            pugi::xml_node emission = common.child(shader).child("emission");
            if (!emission.child("color")) continue;
            Color radiance = expectColor(file_, emission, "color");
            if (maxComponent(radiance) > 0) m.kind = MaterialKind::Emission, m.emission = radiance;
            break;
        }
        pugi::xml_node tech = extraTechnique(effect);
        pugi::xml_node kind = tech.first_child();
        if (!kind) return m;
        std::string k = kind.name();
        const MaterialKindSpec* spec = findMaterialKind(k);
        if (!spec || !spec->inCgl)
            throw SceneError(file_, "unknown CGL material <" + k + "> in effect '" +
                                        effect.attribute("id").as_string() + "'");
        m.kind = spec->kind;
        for (const MaterialParam& p : spec->params) {
            if (p.colour) {
                m.*p.colour = expectColor(file_, kind, p.name);
                continue;
            }
            float v = expectScalar(file_, kind, p.name);
            if (!inRange(p.range, v))
                throw SceneError(file_, "CGL <" + k + "> has " + p.name + " " + std::to_string(v) +
                                            " (must be " + rangeText(p.range) + ")");
            m.*p.scalar = v;
        }
        return m;
    }

    void parseMaterials(pugi::xml_node lib) {
        for (pugi::xml_node mat : lib.children("material")) {
            std::string id = mat.attribute("id").as_string();
            std::string name = mat.attribute("name").as_string(id.c_str());
            std::string effectId = urlTarget(mat.child("instance_effect").attribute("url"));
            pugi::xml_node effect = find(effectId);
            if (!effect)
                throw SceneError(file_,
                                 "material '" + id + "' names missing effect '" + effectId + "'");
            out_.materialsById[id] = parseEffect(effect, name);
            out_.materialIdByName[name] = id;
        }
    }

    Mat4 nodeTransform(pugi::xml_node node) {
        Mat4 local;
        bool hasCamera = bool(node.child("instance_camera"));
        for (pugi::xml_node t : node.children()) {
            std::string n = t.name();
            if (n == "matrix") {
                std::vector<double> v = parseNumbers(file_, t, "matrix");
                if (v.size() != 16) {
                    if (!hasCamera || v.size() > 16)
                        throw SceneError(file_,
                                         "node '" + std::string(node.attribute("id").as_string()) +
                                             "' has a <matrix> of " + std::to_string(v.size()) +
                                             " numbers (needs 16)");
                    // CBgems: the course program reads the numbers it finds and leaves the rest 0;
                    // only the camera direction is used, so do the same and say so.
                    out_.warnings.push_back(
                        "camera node '" + std::string(node.attribute("id").as_string()) +
                        "' has a <matrix> of " + std::to_string(v.size()) +
                        " numbers; missing ones read as 0, as the CS184 program does");
                    v.resize(16, 0.0);
                    // Assimp refuses the short matrix; give it an identity so the rest imports.
                    t.text().set("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
                    patched_ = true;
                }
                local = local * matrixFromRowMajor(v);
            } else if (n == "translate") {
                std::vector<double> v = expectNumbers(file_, t, "translate", 3);
                Mat4 m;
                m.m[0][3] = v[0], m.m[1][3] = v[1], m.m[2][3] = v[2];
                local = local * m;
            } else if (n == "scale") {
                std::vector<double> v = expectNumbers(file_, t, "scale", 3);
                Mat4 m;
                m.m[0][0] = v[0], m.m[1][1] = v[1], m.m[2][2] = v[2];
                local = local * m;
            } else if (n == "rotate") {
                std::vector<double> v = expectNumbers(file_, t, "rotate", 4);
                local = local * rotation(Vec3d(v[0], v[1], v[2]), v[3]);
            }
        }
        return local;
    }

    static Mat4 rotation(Vec3d axis, double degrees) {
        axis = normalize(axis);
        double a = degrees * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
        Mat4 m;
        double x = axis.x, y = axis.y, z = axis.z;
        m.m[0][0] = c + x * x * (1 - c), m.m[0][1] = x * y * (1 - c) - z * s,
        m.m[0][2] = x * z * (1 - c) + y * s;
        m.m[1][0] = y * x * (1 - c) + z * s, m.m[1][1] = c + y * y * (1 - c),
        m.m[1][2] = y * z * (1 - c) - x * s;
        m.m[2][0] = z * x * (1 - c) - y * s, m.m[2][1] = z * y * (1 - c) + x * s,
        m.m[2][2] = c + z * z * (1 - c);
        return m;
    }

    void walk(pugi::xml_node node, const Mat4& parent) {
        Mat4 world = parent * nodeTransform(node);
        if (const char* id = node.attribute("id").as_string(); *id) out_.nodeWorldById[id] = world;
        if (node.child("instance_geometry")) placed_.extend(world.point(Vec3d(0.0)));
        for (pugi::xml_node child : node.children("node")) walk(child, world);
        for (pugi::xml_node inst : node.children("instance_geometry")) addSphere(inst, world);
        for (pugi::xml_node inst : node.children("instance_light")) addLight(inst, world);
        for (pugi::xml_node inst : node.children("instance_camera")) addCamera(inst, world);
    }

    void addSphere(pugi::xml_node inst, const Mat4& world) {
        std::string geomId = urlTarget(inst.attribute("url"));
        pugi::xml_node geom = find(geomId);
        if (!geom)
            throw SceneError(file_, "instance_geometry names missing geometry '" + geomId + "'");
        if (geom.child("mesh")) return;  // triangles come through Assimp
        pugi::xml_node sphereNode = extraTechnique(geom).child("sphere");
        if (!sphereNode) return;
        Sphere s;
        // The object is the node that places the sphere (CBspheres.dae's "Sphere2" instances
        // "Sphere1-data"); the geometry's name when the node has none.
        pugi::xml_node node = inst.parent();
        s.name = node.attribute("name").as_string(
            node.attribute("id").as_string(geom.attribute("name").as_string(geomId.c_str())));
        float radius = expectScalar(file_, sphereNode, "radius");
        if (!(radius > 0))
            throw SceneError(file_, "sphere '" + geomId + "' has radius " + std::to_string(radius));
        // As the course program: centre = M*(0,0,0), radius scaled by the length of M*(1,0,0).
        s.radius = radius * float(length(world.vector(Vec3d(1, 0, 0))));
        out_.spheres.push_back(s);
        sphereCentres_.push_back(world.point(Vec3d(0, 0, 0)));
        pugi::xml_node bind =
            inst.child("bind_material").child("technique_common").child("instance_material");
        const std::string materialId = urlTarget(bind.attribute("target"));
        // Here, before Assimp imports the file's meshes (the materials are parsed already).
        if (!materialId.empty() && !out_.materialsById.count(materialId))
            throw SceneError(file_,
                             "sphere '" + s.name + "' binds unknown material '" + materialId + "'");
        out_.sphereMaterialIds.push_back(materialId);
    }

    void addLight(pugi::xml_node inst, const Mat4& world) {
        std::string id = urlTarget(inst.attribute("url"));
        pugi::xml_node def = find(id);
        if (!def) throw SceneError(file_, "instance_light names missing light '" + id + "'");
        Light light;
        light.name = def.attribute("name").as_string(id.c_str());
        pugi::xml_node kind = extraTechnique(def).first_child();
        if (!kind) kind = def.child("technique_common").first_child();
        if (!kind) throw SceneError(file_, "light '" + id + "' has no supported technique");
        std::string k = kind.name();
        light.radiance = expectColor(file_, kind, "color");
        const bool common = !courseLights_ && kind.parent() == def.child("technique_common");
        lightPositions_.push_back(world.point(Vec3d(0, 0, 0)));
        Vec3d dir = world.vector(Vec3d(0, 0, -1));
        light.direction = Vec3(normalize(dir));
        if (k == "area") {
            light.kind = LightKind::Area;
            light.dimX = Vec3(world.vector(Vec3d(-1, 0, 0)));
            light.dimY = Vec3(world.vector(Vec3d(0, 1, 0)));
        } else if (k == "point") {
            light.kind = LightKind::Point;
        } else if (k == "spot") {
            light.kind = LightKind::Spot;
            if (pugi::xml_node angle = kind.child("falloff_angle"))
                light.spotOuterDeg =
                    float(expectNumbers(file_, angle, "falloff_angle", 1)[0]) * 0.5f;
            light.spotInnerDeg = light.spotOuterDeg * 0.85f;
        } else if (k == "directional") {
            light.kind = LightKind::Directional;
        } else if (k == "ambient") {
            light.kind = LightKind::Ambient;
            light.direction =
                Vec3(0, 1, 0);  // CS184's hemisphere light: the upper (+Y) hemisphere emits
        } else {
            throw SceneError(file_, "light '" + id + "' has unsupported type <" + k + ">");
        }
        if (common) commonProfileUnits(kind, world, light);
        out_.lights.push_back(light);
    }

    // COLLADA's common profile lights a <lambert> surface as diffuse * colour * attenuation *
    // max(N.L, 0), with attenuation 1 / (constant + linear d + quadratic d^2) (defaults 1, 0, 0:
    // no falloff). kiln's Lambertian reflects albedo / pi of the irradiance, so the intensity (and
    // a directional light's irradiance) is pi * colour and the falloff the file's own: exact. A
    // spot's falloff_exponent and an ambient light (which COLLADA scales by each material's
    // ambient colour) are approximated, with a warning.
    void commonProfileUnits(pugi::xml_node kind, const Mat4& world, Light& light) {
        std::string k = kind.name();
        if (k == "ambient") {
            out_.warnings.push_back("light '" + light.name +
                                    "': a COLLADA ambient light scales each material's ambient "
                                    "colour; kiln lights the scene with a sky of its colour from "
                                    "above instead");
            return;
        }
        // 3ds Max and FCollada exporters put the light's multiplier in their own technique.
        float multiplier = 1;
        if (pugi::xpath_node n = kind.parent().parent().select_node(
                ".//technique[@profile='MAX3D' or @profile='FCOLLADA']/intensity"))
            multiplier = float(expectNumbers(file_, n.node(), "intensity", 1)[0]);
        light.radiance = light.radiance * (kPi * multiplier);
        if (k != "point" && k != "spot") return;
        // Distances in the file's units; kiln's are metres (the unit and node scale applied).
        double scale = length(world.vector(Vec3d(1, 0, 0)));
        auto number = [&](const char* name, double fallback) {
            pugi::xml_node n = kind.child(name);
            return n ? expectNumbers(file_, n, name, 1)[0] : fallback;
        };
        double c = number("constant_attenuation", 1), l = number("linear_attenuation", 0),
               q = number("quadratic_attenuation", 0);
        if (!(c >= 0 && l >= 0 && q >= 0 && c + l + q > 0))
            throw SceneError(
                file_, "light '" + light.name + "' has negative or all-zero attenuation factors");
        light.attenuationStated = true;
        light.attenuationConstant = float(c);
        light.attenuationLinear = scale > 0 ? float(l / scale) : float(l);
        light.attenuationQuadratic = scale > 0 ? float(q / (scale * scale)) : float(q);
        if (k == "spot" && number("falloff_exponent", 0) > 0)
            out_.warnings.push_back(
                "light '" + light.name +
                "': the spot's falloff_exponent (cos^n within the cone) is approximated by kiln's "
                "soft edge over the outer 15 % of the cone");
    }

    void addCamera(pugi::xml_node inst, const Mat4& world) {
        std::string id = urlTarget(inst.attribute("url"));
        pugi::xml_node def = find(id);
        if (!def) throw SceneError(file_, "instance_camera names missing camera '" + id + "'");
        pugi::xml_node optics = def.child("optics").child("technique_common");
        pugi::xml_node persp = optics.child("perspective");
        if (pugi::xml_node ortho = optics.child("orthographic"))
            persp = ortho;
        else if (!persp)
            throw SceneError(file_,
                             "camera '" + id + "' has neither <perspective> nor <orthographic>");
        Camera cam = persp.name() == std::string("orthographic")
                         ? orthographicCamera(id, persp, world)
                         : perspectiveCamera(id, persp);
        cam.name = def.attribute("name").as_string(id.c_str());
        placeCamera(cam, persp, world);
    }

    Camera perspectiveCamera(const std::string& id, pugi::xml_node persp) {
        Camera cam;
        pugi::xml_node xfov = persp.child("xfov"), yfov = persp.child("yfov"),
                       aspect = persp.child("aspect_ratio");
        cam.hFovDeg = xfov ? float(expectNumbers(file_, xfov, "xfov", 1)[0]) : 50.0f;
        cam.vFovDeg = yfov ? float(expectNumbers(file_, yfov, "yfov", 1)[0]) : 35.0f;
        if (!yfov && aspect) {
            float ar = float(expectNumbers(file_, aspect, "aspect_ratio", 1)[0]);
            if (!(ar > 0)) throw SceneError(file_, "camera '" + id + "' has aspect_ratio <= 0");
            cam.vFovDeg = degrees(2.0f * std::atan(std::tan(radians(0.5f * cam.hFovDeg)) / ar));
        } else if (!xfov && yfov && aspect) {
            float ar = float(expectNumbers(file_, aspect, "aspect_ratio", 1)[0]);
            cam.hFovDeg = degrees(2.0f * std::atan(std::tan(radians(0.5f * cam.vFovDeg)) * ar));
        }
        if (!(cam.hFovDeg > 0 && cam.hFovDeg < 180 && cam.vFovDeg > 0 && cam.vFovDeg < 180))
            throw SceneError(file_,
                             "camera '" + id + "' has a field of view outside (0, 180) degrees");
        return cam;
    }

    // <orthographic>: xmag and ymag are half the view's width and height in the camera node's
    // units (Blender writes its orthographic scale / 2); one of them with aspect_ratio gives the
    // other.
    Camera orthographicCamera(const std::string& id, pugi::xml_node ortho, const Mat4& world) {
        auto number = [&](const char* name) {
            pugi::xml_node n = ortho.child(name);
            return n ? expectNumbers(file_, n, name, 1)[0] : 0.0;
        };
        double xmag = number("xmag"), ymag = number("ymag"), aspect = number("aspect_ratio");
        if (aspect > 0 && !(ymag > 0)) ymag = xmag / aspect;
        if (aspect > 0 && !(xmag > 0)) xmag = ymag * aspect;
        if (!(xmag > 0)) xmag = ymag;
        if (!(ymag > 0)) ymag = xmag;
        Camera cam;
        cam.orthoHalfWidth = float(xmag * length(world.vector(Vec3d(1, 0, 0))));
        cam.orthoHalfHeight = float(ymag * length(world.vector(Vec3d(0, 1, 0))));
        if (!(cam.orthoHalfWidth > 0 && cam.orthoHalfHeight > 0 &&
              std::isfinite(cam.orthoHalfWidth) && std::isfinite(cam.orthoHalfHeight)))
            throw SceneError(
                file_, "orthographic camera '" + id + "' has no positive, finite xmag or ymag");
        return cam;
    }

    // Places a camera read from its optics: the node's -Z is the view, +Y up.
    void placeCamera(Camera cam, pugi::xml_node persp, const Mat4& world) {
        Vec3d fwd = world.vector(Vec3d(0, 0, -1)), up = world.vector(Vec3d(0, 1, 0));
        // Clip distances are in the camera node's units (the <unit> and any node scale).
        if (pugi::xml_node n = persp.child("znear"))
            cam.nearClip = float(expectNumbers(file_, n, "znear", 1)[0] * length(fwd));
        if (pugi::xml_node f = persp.child("zfar"))
            cam.farClip = float(expectNumbers(file_, f, "zfar", 1)[0] * length(fwd));
        cameraPosition_ = world.point(Vec3d(0, 0, 0));
        if (length(fwd) > 0) cam.forward = Vec3(normalize(fwd));
        if (length(up) > 0) cam.up = Vec3(normalize(up));
        // The course keeps only normalize(M * (view_dir, 1)), translation included.
        Vec3d c = world.point(Vec3d(0, 0, -1));
        if (length(c) > 0) cam.cs184Direction = Vec3(normalize(c));
        cam.fromFile = true;
        out_.camera = cam;
    }

    // The origin follows what the file places (originFor); positions wait for it in double.
    void storeRelativeToOrigin() {
        for (const Vec3d& c : sphereCentres_) placed_.extend(c);
        for (const Vec3d& p : lightPositions_) placed_.extend(p);
        out_.origin = originFor(placed_);
        for (size_t i = 0; i < out_.spheres.size(); ++i)
            out_.spheres[i].center = Vec3(sphereCentres_[i] - out_.origin);
        for (size_t i = 0; i < out_.lights.size(); ++i)
            out_.lights[i].position = Vec3(lightPositions_[i] - out_.origin);
        if (out_.camera) out_.camera->position = Vec3(cameraPosition_ - out_.origin);
    }

    const std::string& file_;
    pugi::xml_document& doc_;
    Bounds3T<double> placed_;
    std::vector<Vec3d> sphereCentres_, lightPositions_;
    Vec3d cameraPosition_{0.0};
    std::map<std::string, pugi::xml_node> byId_;
    ColladaExtras out_;
    bool patched_ = false;
    bool courseLights_ = false;
};

}  // namespace

ColladaExtras parseColladaExtras(const std::string& path) {
    pugi::xml_document doc;
    pugi::xml_parse_result result = doc.load_file(path.c_str());
    if (!result)
        throw SceneError(path, std::string("malformed XML at byte ") +
                                   std::to_string(result.offset) + ": " + result.description());
    return Parser(path, doc).run();
}

}  // namespace kiln
