#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>

#include "scene/importers.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

// Assimp's file access, noting every file it opens (an OBJ's .mtl, a glTF's .bin, COLLADA external
// references, the scene file itself): the checkpoint fingerprint checksums them with the scene,
// and drops repeats and the scene file there (by canonical path, which spellings here would miss).
class RecordingIOSystem : public Assimp::DefaultIOSystem {
  public:
    explicit RecordingIOSystem(std::vector<std::string>& opened) : opened_(opened) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        Assimp::IOStream* stream = DefaultIOSystem::Open(file, mode);
        if (stream) opened_.push_back(file);
        return stream;
    }

  private:
    std::vector<std::string>& opened_;
};

Mat4 toMat4(const aiMatrix4x4& a) {
    Mat4 m;
    const ai_real* src = &a.a1;  // aiMatrix4x4 is row-major a1..d4
    for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = src[i];
    return m;
}

Vec3d toVec3d(const aiVector3D& v) { return {v.x, v.y, v.z}; }

// The file's tangents (glTF TANGENT; Assimp gives the bitangent cross(n, t) * w): xyz and the
// handedness sign, placed by `xf` when the mesh is baked (a mirror flips the sign).
void readFileTangents(const aiMesh* am, const Mat4* xf, TriangleMesh& mesh) {
    bool mirror = xf && xf->determinant3() < 0;
    mesh.tangents.reserve(4 * am->mNumVertices);
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
        Vec3 t(am->mTangents[v].x, am->mTangents[v].y, am->mTangents[v].z);
        Vec3 b(am->mBitangents[v].x, am->mBitangents[v].y, am->mBitangents[v].z);
        Vec3 n(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
        float sign = dot(cross(n, t), b) < 0 ? -1.0f : 1.0f;
        if (xf) t = xf->vector(t);
        float len = length(t);
        if (len > 0) t = t / len;
        mesh.tangents.insert(mesh.tangents.end(), {t.x, t.y, t.z, mirror ? -sign : sign});
    }
}

// cglRules (COLLADA): an emissive material is a light and nothing else, as in the course. Other
// formats add the emission to the surface, which still reflects (Lambert, or principled where the
// file states metallic-roughness).
Material materialFromAssimp(const aiMaterial* am, bool cglRules, bool gltf, PhongDialect phong) {
    Material m;  // albedo keeps the default grey unless the file states a diffuse colour
    aiString name;
    if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
    // Get() overwrites its argument even when the key is missing: only a success counts.
    aiColor3D diffuse, emissive;
    if (am->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS)
        m.albedo = Color(diffuse.r, diffuse.g, diffuse.b);
    if (am->Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS &&
        (emissive.r > 0 || emissive.g > 0 || emissive.b > 0)) {
        m.emission = Color(emissive.r, emissive.g, emissive.b);
        if (cglRules) m.kind = MaterialKind::Emission;
    }
    if (cglRules) return m;
    float strength = 1;  // KHR_materials_emissive_strength
    if (am->Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) == AI_SUCCESS && std::isfinite(strength))
        m.emission = m.emission * std::max(0.0f, strength);
    if (!readPrincipled(am, gltf, m)) readPhongSpecular(am, phong, m);
    return m;
}

// What Assimp 5.2 leaves out of a glTF material (gltf_extensions.cpp).
void applyGltfExtras(const aiMaterial* am, const GltfMaterialExtras& x, Material& m, Scene& scene) {
    float stated = 1;
    if (am->Get(AI_MATKEY_EMISSIVE_INTENSITY, stated) != AI_SUCCESS)
        m.emission = m.emission * x.emissiveStrength;
    if (m.kind != MaterialKind::Principled) return;
    if (x.specular) m.specular = *x.specular;
    if (x.specularColour) m.specularColor = *x.specularColour;
    for (const std::string& texture : x.unreadTextures)
        scene.warnings.push_back(
            (m.name.empty() ? "an unnamed material" : "material '" + m.name + "'") +
            ": KHR_materials_specular " + texture + " ignored");
}

// Assimp's MDL reader gives a model without skins a zero-initialised colour, alpha 0 included
// (PhosphoricAcid_MDl5.mdl renders black); no file states a diffuse colour of alpha 0.
bool unsetMdlColour(const std::string& path, const aiMaterial* am) {
    aiColor4D c;
    return lowerExtension(path) == ".mdl" && am->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS &&
           c.r == 0 && c.g == 0 && c.b == 0 && c.a == 0;
}

// Assimp's AMF reader gives a mesh whose file states no vertex colours a colour set of zeros,
// alpha included (test1.amf renders black); its Blender reader one of (-1, -1, -1, -1)
// (BlenderDefault_250.blend renders black). Neither is a colour: all zero, or any negative.
bool unsetColours(const aiMesh* am) {
    bool allZero = true;
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
        const aiColor4D& c = am->mColors[0][v];
        if (c.r < 0 || c.g < 0 || c.b < 0) return true;
        allZero &= c.r == 0 && c.g == 0 && c.b == 0 && c.a == 0;
    }
    return allZero;
}

// Assimp 5.2's AMF reader stores <rx>/<ry>/<rz> of a constellation instance into its
// <deltax>/<deltay>/<deltaz> and drops the rotation (test8.amf: instances at x = -45 and 45 instead
// of -5 and 5), and keeps only the first <volume> of an object.
void warnAmfLimits(const std::string& path, Scene& scene) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("<constellation") != std::string::npos)
        scene.warnings.push_back(
            "Assimp misplaces AMF constellation instances (their rotation "
            "<rx>/<ry>/<rz> replaces the offset <deltax>/<deltay>/<deltaz>)");
    size_t volumes = 0;
    for (size_t at = text.find("<volume"); at != std::string::npos;
         at = text.find("<volume", at + 1))
        ++volumes;
    size_t objects = 0;
    for (size_t at = text.find("<object"); at != std::string::npos;
         at = text.find("<object", at + 1))
        ++objects;
    if (volumes > objects)
        scene.warnings.push_back(
            "Assimp imports only the first <volume> of each AMF object; the "
            "others are missing");
}

// Assimp reports some silent repairs only through its logger: this collects them for one import.
class AssimpLog {
  public:
    AssimpLog() {
        Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
        Assimp::DefaultLogger::get()->attachStream(new Stream(messages_),
                                                   Assimp::Logger::Warn | Assimp::Logger::Err);
    }
    ~AssimpLog() { Assimp::DefaultLogger::kill(); }
    AssimpLog(const AssimpLog&) = delete;
    AssimpLog& operator=(const AssimpLog&) = delete;
    bool said(const std::string& text) const {
        return std::any_of(messages_.begin(), messages_.end(),
                           [&](const std::string& m) { return m.find(text) != std::string::npos; });
    }

  private:
    struct Stream : Assimp::LogStream {
        explicit Stream(std::vector<std::string>& out) : out_(out) {}
        void write(const char* message) override { out_.emplace_back(message); }
        std::vector<std::string>& out_;
    };
    std::vector<std::string> messages_;
};

// Some of Assimp's parsers (OpenGEX's openddl: "nullptr returned by creating DDLNode.") print to
// std::cerr, which broke kiln's one-line errors; while Assimp reads, what they print is collected
// and becomes warnings.
class CerrCapture {
  public:
    CerrCapture() : old_(std::cerr.rdbuf(text_.rdbuf())) {}
    ~CerrCapture() { stop(); }
    void stop() {
        if (old_) std::cerr.rdbuf(old_);
        old_ = nullptr;
    }
    CerrCapture(const CerrCapture&) = delete;
    CerrCapture& operator=(const CerrCapture&) = delete;
    void addWarnings(Scene& scene) const {
        std::istringstream lines(text_.str());
        for (std::string line; std::getline(lines, line);)
            if (!line.empty()) scene.warnings.push_back("Assimp: " + line);
    }

  private:
    std::ostringstream text_;
    std::streambuf* old_;
};

// Assimp's OFF reader reserves what the header declares and then loops over it: a header claiming
// 353535235358 vertices (assimp-testmodels' invalid/OutOfMemory.off) runs for minutes. Counts the
// file cannot hold are refused first (each vertex or face takes at least 6 bytes of text).
void checkOffHeader(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> tokens;
    std::string line;
    while (tokens.size() < 4 && std::getline(in, line)) {
        std::istringstream words(line.substr(0, line.find('#')));
        for (std::string w; tokens.size() < 4 && words >> w;) tokens.push_back(w);
    }
    if (tokens.size() < 3) return;  // Assimp reports it
    size_t first = tokens[0].find("OFF") != std::string::npos ? 1 : 0;
    uint64_t limit = std::filesystem::file_size(path) / 6 + 1, counts[2] = {0, 0};
    for (int i = 0; i < 2 && first + size_t(i) < tokens.size(); ++i) {
        const std::string& t = tokens[first + size_t(i)];
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), counts[i]);
        if (ec != std::errc() || end != t.data() + t.size())
            throw SceneError(path, "OFF header count '" + t + "' is not a non-negative integer");
        if (counts[i] > limit)
            throw SceneError(path, "OFF header declares " + t + (i ? " faces" : " vertices") +
                                       ", more than the file can hold");
    }
    checkMemoryFor(path, counts[0], counts[1]);
}

struct NodeVisit {
    const aiNode* node;
    Mat4 world;
};

// World transform of every node, composed in double. COLLADA nodes take the kiln XML pass's
// matrices (parsed in double) where the node id is known, so a translation of 1e7 keeps its digits.
using NodeWorlds = std::vector<std::pair<const aiNode*, Mat4>>;  // in visiting order

NodeWorlds nodeWorlds(const aiScene* as, const ColladaExtras* extras) {
    NodeWorlds world;
    Mat4 rootFix = extras ? extras->upAxisFix : Mat4::identity();
    std::vector<NodeVisit> stack{{as->mRootNode, rootFix * toMat4(as->mRootNode->mTransformation)}};
    while (!stack.empty()) {
        NodeVisit v = stack.back();
        stack.pop_back();
        if (extras) {
            auto exact = extras->nodeWorldById.find(v.node->mName.C_Str());
            if (exact != extras->nodeWorldById.end()) v.world = exact->second;
        }
        world.emplace_back(v.node, v.world);
        for (unsigned c = 0; c < v.node->mNumChildren; ++c)
            stack.push_back(
                {v.node->mChildren[c], v.world * toMat4(v.node->mChildren[c]->mTransformation)});
    }
    return world;
}

// The object a node's meshes make, by the node's name; not the root, which holds a format's loose
// meshes (an OBJ's groups, an STL's solids) under a name of the importer's.
std::string objectName(const aiScene* as, const aiNode* node) {
    return node == as->mRootNode ? std::string() : std::string(node->mName.C_Str());
}

Mat4 worldOf(const aiScene* as, const NodeWorlds& worlds, const aiString& name) {
    const aiNode* node = as->mRootNode->FindNode(name);
    for (const auto& [n, world] : worlds)
        if (n == node) return world;
    return Mat4::identity();
}

// The view a camera's file states, in world space, before kiln's Camera is set from it.
struct CameraView {
    Vec3d position, look, up;
    float hFovDeg = 0;   // full horizontal angle (perspective)
    double lengthScale;  // the camera node's scale along its view axis (clip planes, ortho width)
    bool clipPlanes = true;  // false: Assimp's clip planes are its defaults, not the file's
};

// 3DS: from the file's own camera chunk (read3dsCamera), placed by Assimp's root node (its Z-up to
// Y-up rotation), since Assimp 5.2 drops the target and reads the lens as an angle.
std::optional<CameraView> view3ds(const std::string& path, const aiCamera* ac,
                                  const NodeWorlds& worlds) {
    std::optional<Camera3ds> c = read3dsCamera(path, ac->mName.C_Str());
    if (!c) return std::nullopt;
    const Mat4& root = worlds.front().second;
    CameraView v;
    v.position = root.point(Vec3d(c->position));
    v.look = root.point(Vec3d(c->target)) - v.position;
    Vec3d f = normalize(v.look), up = root.vector(Vec3d(0, 0, 1));
    double bank = radians(double(c->bankDeg));  // about the view axis, right-handed (as Assimp)
    v.up = up * std::cos(bank) + cross(f, up) * std::sin(bank) +
           f * (dot(f, up) * (1 - std::cos(bank)));
    v.hFovDeg = fovFrom3dsLens(c->lensMm);
    v.lengthScale = 1;
    v.clipPlanes = false;  // 3DS cameras state no clip planes; Assimp's far 1000 is made up
    return v;
}

CameraView viewFromAssimp(const std::string& ext, const aiScene* as, const aiCamera* ac,
                          const NodeWorlds& worlds) {
    Mat4 world = worldOf(as, worlds, ac->mName);
    bool gltf = ext == ".gltf" || ext == ".glb";
    CameraView v;
    // glTF: Assimp copies the node's translation into mPosition, which the node already applies.
    v.position = world.point(gltf ? Vec3d(0.0) : toVec3d(ac->mPosition));
    v.look = world.vector(toVec3d(ac->mLookAt)), v.up = world.vector(toVec3d(ac->mUp));
    // ASE, LWS and OpenGEX cameras look down their node's -Z, but Assimp reports +Z (OpenGEX:
    // Blender's exporter writes its camera matrix, whose -Z is the view, as the corpus files show).
    if (ext == ".ase" || ext == ".lws" || ext == ".ogex") v.look = -v.look;
    v.lengthScale = length(v.look) / length(toVec3d(ac->mLookAt));
    if (gltf && ac->mAspect > 0) {
        // glTF states yfov; Assimp stores yfov * aspect, so the ratio gives back the file's value.
        float vFov = ac->mHorizontalFOV / ac->mAspect;
        v.hFovDeg = degrees(2.0f * std::atan(std::tan(0.5f * vFov) * ac->mAspect));
    } else {
        v.hFovDeg = degrees(ac->mHorizontalFOV);
    }
    return v;
}

// The first usable camera. Assimp 5.2 stores the full horizontal angle in mHorizontalFOV (checked
// against the files: Blender 49.13 degrees, NFF "angle 60", COLLADA yfov with aspect 1), and
// per-format quirks checked on assimp-testmodels are undone here (docs/import.md).
void readCamera(const std::string& path, const aiScene* as, const NodeWorlds& worlds,
                Scene& scene) {
    std::string ext = lowerExtension(path);
    const aiCamera* ac = as->mCameras[0];
    std::string name = ac->mName.C_Str();
    bool ortho = ac->mOrthographicWidth > 0;
    if (!ortho && !(ac->mHorizontalFOV > 0)) {
        scene.warnings.push_back("camera '" + name +
                                 "' states no field of view; using the default framing instead");
        return;
    }
    std::optional<CameraView> view =
        ext == ".3ds" ? view3ds(path, ac, worlds) : viewFromAssimp(ext, as, ac, worlds);
    if (!view) {
        scene.warnings.push_back("camera '" + name +
                                 "': no camera chunk of that name in the 3DS file; using the "
                                 "default framing instead");
        return;
    }
    if (!(length(view->look) > 0) || !(length(view->up) > 0) || !isFinite(Vec3(view->position)))
        throw SceneError(path, "camera '" + name + "' has no valid position or direction");
    Camera& cam = scene.camera;
    float aspect = ac->mAspect > 0 ? ac->mAspect : 4.0f / 3.0f;
    if (ortho) {  // mOrthographicWidth: half the width (glTF xmag); the height from mAspect
        cam.orthoHalfWidth = float(ac->mOrthographicWidth * view->lengthScale);
        cam.orthoHalfHeight = cam.orthoHalfWidth / aspect;
    } else {
        cam.hFovDeg = view->hFovDeg;
        cam.vFovDeg = degrees(2.0f * std::atan(std::tan(radians(0.5f * cam.hFovDeg)) / aspect));
    }
    cam.position = scene.stored(view->position);
    cam.forward = Vec3(normalize(view->look));
    cam.up = Vec3(normalize(view->up));
    // Clip distances are in the camera node's units: scale them as the node scales its view axis.
    if (view->clipPlanes && ac->mClipPlaneNear > 0)
        cam.nearClip = float(ac->mClipPlaneNear * view->lengthScale);
    if (view->clipPlanes && ac->mClipPlaneFar > ac->mClipPlaneNear)
        cam.farClip = float(ac->mClipPlaneFar * view->lengthScale);
    cam.name = name;
    cam.fromFile = true;
    scene.hasFileCamera = true;
}

// kiln's point and spot lights fall off with the square of the distance, as physics says. FBX
// states its falloff (DecayType and DecayStart, which Assimp turns into these factors): kiln uses
// it (huesitos.fbx's lamp: linear, 1 / (0.000667 d), rendered black as 1 / d^2). Other readers
// fill the factors with their own defaults (Assimp's aiLight: linear 1), so they keep 1 / d^2 and
// a stated falloff other than quadratic is a warning.
void readAttenuation(const std::string& path, const aiLight* al, Light& l, Scene& scene) {
    if (al->mType != aiLightSource_POINT && al->mType != aiLightSource_SPOT) return;
    bool stated =
        al->mAttenuationConstant > 0 || al->mAttenuationLinear > 0 || al->mAttenuationQuadratic > 0;
    if (lowerExtension(path) == ".fbx" && stated) {
        l.attenuationStated = true;
        l.attenuationConstant = al->mAttenuationConstant;
        l.attenuationLinear = al->mAttenuationLinear;
        l.attenuationQuadratic = al->mAttenuationQuadratic;
        return;
    }
    // Only a quadratic term (glTF: 1, the colour in candela): intensity = colour / q, exact.
    if (al->mAttenuationQuadratic > 0 && al->mAttenuationConstant == 0 &&
        al->mAttenuationLinear == 0) {
        l.radiance = l.radiance * float(1.0 / al->mAttenuationQuadratic);
        return;
    }
    if (al->mAttenuationQuadratic > 0 ||
        !(al->mAttenuationConstant > 0 || al->mAttenuationLinear > 0))
        return;
    char msg[240];
    std::snprintf(msg, sizeof msg,
                  "light '%s': Assimp reports attenuation constant %g linear %g quadratic 0 (for "
                  "this format possibly its own default); kiln keeps the physical 1 / d^2",
                  al->mName.C_Str(), al->mAttenuationConstant, al->mAttenuationLinear);
    scene.warnings.push_back(msg);
}

// FBX states a spot's cone as its full angle (Blender's spot size, Maya's cone angle), Assimp
// passes it on; glTF and kiln measure from the axis.
void readLights(const std::string& path, const aiScene* as, const NodeWorlds& worlds,
                Scene& scene) {
    float coneScale = lowerExtension(path) == ".fbx" ? 0.5f : 1.0f;
    LightConventions conventions = as->mNumLights ? lightConventionsOf(path) : LightConventions{};
    for (unsigned i = 0; i < as->mNumLights; ++i) {
        const aiLight* al = as->mLights[i];
        Mat4 world = worldOf(as, worlds, al->mName);
        Light l;
        l.name = al->mName.C_Str();
        l.radiance = Color(al->mColorDiffuse.r, al->mColorDiffuse.g, al->mColorDiffuse.b);
        l.position = scene.stored(world.point(toVec3d(al->mPosition)));
        // SIB: Assimp 5.2 reports the light's target point as its direction (heffalump.sib's sun
        // would shine upwards).
        Vec3d aim = lowerExtension(path) == ".sib"
                        ? toVec3d(al->mDirection) - toVec3d(al->mPosition)
                        : toVec3d(al->mDirection);
        Vec3 dir = Vec3(world.vector(aim));
        if (length(dir) > 0) l.direction = normalize(dir);
        switch (al->mType) {
            case aiLightSource_POINT:
                l.kind = LightKind::Point;
                break;
            case aiLightSource_SPOT:
                l.kind = LightKind::Spot;
                l.spotInnerDeg = coneScale * degrees(al->mAngleInnerCone);
                l.spotOuterDeg = coneScale * degrees(al->mAngleOuterCone);
                break;
            case aiLightSource_DIRECTIONAL:
                l.kind = LightKind::Directional;
                break;
            case aiLightSource_AMBIENT:
                l.kind = LightKind::Ambient;
                l.direction = Vec3(0, 1, 0);
                break;
            case aiLightSource_AREA: {
                l.kind = LightKind::Area;
                Vec3 up = Vec3(world.vector(toVec3d(al->mUp)));
                Vec3 side = normalize(cross(l.direction, up));
                l.dimX = side * al->mSize.x;
                l.dimY = normalize(up) * al->mSize.y;
                break;
            }
            default:
                scene.warnings.push_back("light '" + l.name + "' is of a type kiln ignores");
                continue;
        }
        if (conventions.format == LightConventions::Format::Other)
            readAttenuation(path, al, l, scene);
        else if (!convertLightUnits(path, conventions, al, l, scene))
            continue;
        scene.lights.push_back(l);
    }
}

// The part's origin, from the world bounds (double) of every baked vertex and instance origin.
Vec3d placedOrigin(const aiScene* as, const std::vector<std::vector<Mat4>>& placements) {
    Bounds3T<double> b;
    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        if (placements[mi].empty()) continue;
        if (placements[mi].size() > 1) {
            for (const Mat4& m : placements[mi]) b.extend(m.point(Vec3d(0.0)));
            continue;
        }
        const aiMesh* am = as->mMeshes[mi];
        for (unsigned v = 0; v < am->mNumVertices; ++v)
            b.extend(placements[mi][0].point(toVec3d(am->mVertices[v])));
    }
    return originFor(b);
}

// Assimp 5.2's JoinIdenticalVertices merges vertices that differ only in colour (a glTF quad's
// COLOR_0 bled into its neighbour's shared corner), so a scene with colours keeps the vertices
// as the file indexes them.
const aiScene* joinVerticesUnlessColoured(Assimp::Importer& importer, const aiScene* as) {
    for (unsigned i = 0; i < as->mNumMeshes; ++i)
        if (as->mMeshes[i]->HasVertexColors(0)) return as;
    return importer.ApplyPostProcessing(aiProcess_JoinIdenticalVertices);
}

// Materials some mesh uses: the glTF reader adds a default one that nothing may reference, whose
// features are no one's to warn about.
std::vector<bool> usedMaterials(const aiScene* as) {
    std::vector<bool> used(as->mNumMaterials, false);
    for (unsigned i = 0; i < as->mNumMeshes; ++i)
        if (as->mMeshes[i]->mMaterialIndex < as->mNumMaterials)
            used[as->mMeshes[i]->mMaterialIndex] = true;
    return used;
}

// Parts with no vertices or no faces (an empty "solid" in an ASCII STL beside one with triangles,
// an empty object of a multi-part file) are dropped with a warning each, before Assimp validates
// the scene (its validation refuses the whole file for one empty mesh). Nodes' references are
// renumbered; when nothing is left, the file is refused as having no geometry.
void skipEmptyMeshes(const std::string& path, aiScene* as, Scene& scene) {
    std::vector<unsigned> newIndex(as->mNumMeshes, UINT_MAX);
    unsigned kept = 0;
    for (unsigned i = 0; i < as->mNumMeshes; ++i) {
        aiMesh* m = as->mMeshes[i];
        if (m && m->mNumVertices > 0 && m->mNumFaces > 0 && m->mVertices && m->mFaces) {
            newIndex[i] = kept;
            as->mMeshes[kept++] = m;
            continue;
        }
        std::string name = m ? m->mName.C_Str() : "";
        scene.warnings.push_back(fmt::format("mesh '{}' (part {} of {}) has no {}: skipped", name,
                                             i + 1, as->mNumMeshes,
                                             m && m->mNumVertices > 0 ? "faces" : "vertices"));
        delete m;
    }
    if (kept == as->mNumMeshes) return;
    as->mNumMeshes = kept;  // the dropped ones are deleted: the scene must not free them again
    if (kept == 0)
        throw SceneError(path, "every mesh of the file is empty (no vertices or no faces)");
    std::vector<aiNode*> stack{as->mRootNode};
    while (!stack.empty()) {
        aiNode* node = stack.back();
        stack.pop_back();
        unsigned n = 0;
        for (unsigned j = 0; j < node->mNumMeshes; ++j)
            if (node->mMeshes[j] < newIndex.size() && newIndex[node->mMeshes[j]] != UINT_MAX)
                node->mMeshes[n++] = newIndex[node->mMeshes[j]];
        node->mNumMeshes = n;
        for (unsigned c = 0; c < node->mNumChildren; ++c) stack.push_back(node->mChildren[c]);
    }
}

}  // namespace

void importWithAssimp(const std::string& path, const ColladaExtras* extras, Scene& scene) {
    AssimpLog log;
    Assimp::Importer importer;
    importer.SetIOHandler(new RecordingIOSystem(scene.inputFiles));  // the importer owns it
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    unsigned flags =
        aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* as = nullptr;
    CerrCapture printed;
    // Read without post-processing, drop empty parts, then validate and post-process.
    if (extras && extras->patchedXml)
        as = importer.ReadFileFromMemory(extras->patchedXml->data(), extras->patchedXml->size(), 0,
                                         "dae");
    else {
        if (lowerExtension(path) == ".off") checkOffHeader(path);
        as = importer.ReadFile(path, 0);
    }
    if (as && as->mRootNode && !(as->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        skipEmptyMeshes(path, const_cast<aiScene*>(as), scene);
        as = importer.ApplyPostProcessing(flags);
    }
    printed.stop();
    if (log.said("out-of-range indices"))
        throw SceneError(path, "faces have vertex indices out of range");
    if (!as || !as->mRootNode)
        throw SceneError(path, std::string("cannot import: ") + importer.GetErrorString());
    if (as->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        throw SceneError(path, "cannot import: the file is incomplete");
    printed.addWarnings(scene);
    if (lowerExtension(path) == ".amf") warnAmfLimits(path, scene);
    as = joinVerticesUnlessColoured(importer, as);
    std::vector<GltfMaterialExtras> gltfExtras;
    const std::string ext = lowerExtension(path);
    const bool gltf = ext == ".gltf" || ext == ".glb";
    const PhongDialect phong = ext == ".obj"   ? PhongDialect::Obj
                               : ext == ".fbx" ? PhongDialect::Fbx
                                               : PhongDialect::None;
    if (gltf) {
        warnUnreadGltfExtensions(path, scene);
        gltfExtras = gltfMaterialExtras(path);
    }
    std::vector<bool> used = usedMaterials(as);

    // Materials: through the CGL pass for COLLADA (matched by name or id), else Assimp's colours.
    uint32_t materialBase = uint32_t(scene.materials.size());
    for (unsigned i = 0; i < as->mNumMaterials; ++i) {
        Material m = materialFromAssimp(as->mMaterials[i], extras != nullptr, gltf, phong);
        if (i < gltfExtras.size()) applyGltfExtras(as->mMaterials[i], gltfExtras[i], m, scene);
        aiColor3D diffuse;
        bool statesColour = as->mMaterials[i]->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS;
        if (statesColour && unsetMdlColour(path, as->mMaterials[i])) {
            m.albedo = Material{}.albedo, statesColour = false;
            scene.warnings.push_back(
                "the MDL file has no skin and Assimp gives its material the "
                "colour (0, 0, 0, 0); using the default grey");
        }
        if (extras) {
            auto byId = extras->materialsById.find(m.name);
            if (byId == extras->materialsById.end()) {
                auto idOf = extras->materialIdByName.find(m.name);
                if (idOf != extras->materialIdByName.end())
                    byId = extras->materialsById.find(idOf->second);
            }
            if (byId != extras->materialsById.end()) m = byId->second, statesColour = true;
        }
        readAssimpTextures(as, as->mMaterials[i], path, statesColour, m, scene);
        // COLLADA materials follow the CGL rules (docs/import.md), which say what they keep.
        if (!extras && used[i]) warnDroppedMaterialFeatures(as->mMaterials[i], m, scene);
        scene.materials.push_back(m);
    }
    if (scene.materials.size() == materialBase) scene.materials.push_back(Material{"default"});

    // Count references so a mesh placed once is baked into world space and a shared one is
    // instanced.
    NodeWorlds worlds = nodeWorlds(as, extras);
    std::vector<std::vector<Mat4>> placements(as->mNumMeshes);
    std::vector<std::vector<std::string>> placingNodes(as->mNumMeshes);
    for (const auto& [node, world] : worlds)
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            placements[node->mMeshes[i]].push_back(world);
            placingNodes[node->mMeshes[i]].push_back(objectName(as, node));
        }
    Vec3d origin = adoptOrigin(scene, placedOrigin(as, placements));
    Mat4 toStored = Mat4::identity();
    for (int r = 0; r < 3; ++r) toStored.m[r][3] = -origin[r];

    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        const aiMesh* am = as->mMeshes[mi];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || placements[mi].empty()) continue;
        bool bake = placements[mi].size() == 1;
        const Mat4& xf = placements[mi][0];
        // Keep the winding consistent with the geometric normal; invert once per mesh for the
        // normals.
        bool flip = bake && xf.determinant3() < 0;
        Mat4 inverse = bake ? xf.inverse() : Mat4::identity();
        TriangleMesh mesh;
        mesh.name = am->mName.C_Str();
        if (bake) mesh.node = placingNodes[mi][0];
        mesh.positions.reserve(3 * am->mNumVertices + 1);
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            Vec3d p = toVec3d(am->mVertices[v]);
            Vec3 s = bake ? scene.stored(xf.point(p)) : Vec3(p);
            mesh.positions.insert(mesh.positions.end(), {s.x, s.y, s.z});
        }
        if (am->HasNormals()) {
            mesh.normals.reserve(3 * am->mNumVertices);
            for (unsigned v = 0; v < am->mNumVertices; ++v) {
                Vec3 n(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
                if (bake) n = transformNormal(inverse, n);
                float len = length(n);
                if (len > 0) n = n / len;
                mesh.normals.insert(mesh.normals.end(), {n.x, n.y, n.z});
            }
        }
        if (am->HasTextureCoords(0)) {
            mesh.uvs.reserve(2 * am->mNumVertices);
            for (unsigned v = 0; v < am->mNumVertices; ++v)
                mesh.uvs.insert(mesh.uvs.end(),
                                {am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y});
        }
        if (am->HasTangentsAndBitangents() && am->HasNormals() && am->HasTextureCoords(0))
            readFileTangents(am, bake ? &xf : nullptr, mesh);
        if (am->HasVertexColors(0) && unsetColours(am)) {
            scene.warnings.push_back("mesh '" + mesh.name +
                                     "': the vertex colours Assimp reports are all (0, 0, 0, 0) "
                                     "or negative, not colours the file states; ignored");
        } else if (am->HasVertexColors(0)) {  // glTF COLOR_0 and OBJ "v x y z r g b": linear
            mesh.colors.reserve(3 * am->mNumVertices);
            for (unsigned v = 0; v < am->mNumVertices; ++v)
                mesh.colors.insert(mesh.colors.end(),
                                   {am->mColors[0][v].r, am->mColors[0][v].g, am->mColors[0][v].b});
        }
        mesh.indices.reserve(3 * am->mNumFaces);
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const aiFace& face = am->mFaces[f];
            if (face.mNumIndices != 3) continue;
            if (flip)
                mesh.indices.insert(mesh.indices.end(),
                                    {face.mIndices[0], face.mIndices[2], face.mIndices[1]});
            else
                mesh.indices.insert(mesh.indices.end(),
                                    {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
        }
        mesh.materialIds = {materialBase + am->mMaterialIndex};
        mesh.finalizePadding();
        uint32_t meshIndex = uint32_t(scene.meshes.size());
        scene.meshes.push_back(std::move(mesh));
        if (!bake)
            for (size_t k = 0; k < placements[mi].size(); ++k)
                scene.instances.push_back(
                    Instance::place(meshIndex, toStored * placements[mi][k], placingNodes[mi][k]));
    }

    if (extras) return;  // COLLADA lights and camera come from the CGL pass
    if (lowerExtension(path) == ".q3s" || lowerExtension(path) == ".q3o") {
        // Assimp 5.2 gives a Quick3D scene a camera at the origin (inside WusonOrange.q3s) and a
        // light of colour 0: neither is the file's view.
        if (as->mNumCameras > 0 || as->mNumLights > 0)
            scene.warnings.push_back(
                "Assimp does not read the Quick3D scene's camera and light (camera at the origin, "
                "light black); using the default framing and light rig instead");
        return;
    }
    readLights(path, as, worlds, scene);
    if (as->mNumCameras > 0) readCamera(path, as, worlds, scene);
}

}  // namespace kiln
