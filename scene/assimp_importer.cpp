#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <map>

#include "scene/importers.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

Mat4 toMat4(const aiMatrix4x4& a) {
    Mat4 m;
    const ai_real* src = &a.a1;  // aiMatrix4x4 is row-major a1..d4
    for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = src[i];
    return m;
}

Material materialFromAssimp(const aiMaterial* am) {
    Material m;
    aiString name;
    if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
    aiColor3D diffuse(0.5f, 0.5f, 0.5f), emissive(0, 0, 0);
    am->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse);
    m.albedo = Color(diffuse.r, diffuse.g, diffuse.b);
    if (am->Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS &&
        (emissive.r > 0 || emissive.g > 0 || emissive.b > 0)) {
        m.kind = MaterialKind::Emission;
        m.emission = Color(emissive.r, emissive.g, emissive.b);
    }
    return m;
}

struct NodeVisit {
    const aiNode* node;
    Mat4 world;
};

}  // namespace

void importWithAssimp(const std::string& path, const ColladaExtras* extras, Scene& scene) {
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                     aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* as = nullptr;
    if (extras && extras->patchedXml)
        as = importer.ReadFileFromMemory(extras->patchedXml->data(), extras->patchedXml->size(),
                                         flags, "dae");
    else
        as = importer.ReadFile(path, flags);
    if (!as || !as->mRootNode)
        throw SceneError(path, std::string("cannot import: ") + importer.GetErrorString());
    if (as->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        throw SceneError(path, "cannot import: the file is incomplete");

    // Materials: through the CGL pass for COLLADA (matched by name or id), else Assimp's colours.
    uint32_t materialBase = uint32_t(scene.materials.size());
    for (unsigned i = 0; i < as->mNumMaterials; ++i) {
        Material m = materialFromAssimp(as->mMaterials[i]);
        if (extras) {
            auto byId = extras->materialsById.find(m.name);
            if (byId == extras->materialsById.end()) {
                auto idOf = extras->materialIdByName.find(m.name);
                if (idOf != extras->materialIdByName.end())
                    byId = extras->materialsById.find(idOf->second);
            }
            if (byId != extras->materialsById.end()) m = byId->second;
        }
        scene.materials.push_back(m);
    }
    if (scene.materials.size() == materialBase) scene.materials.push_back(Material{"default"});

    // Count references so a mesh placed once is baked into world space and a shared one is
    // instanced.
    std::vector<std::vector<Mat4>> placements(as->mNumMeshes);
    Mat4 rootFix = extras ? extras->upAxisFix : Mat4::identity();
    std::vector<NodeVisit> stack{{as->mRootNode, rootFix * toMat4(as->mRootNode->mTransformation)}};
    std::map<std::string, Mat4> nodeWorld;
    while (!stack.empty()) {
        NodeVisit v = stack.back();
        stack.pop_back();
        nodeWorld[v.node->mName.C_Str()] = v.world;
        for (unsigned i = 0; i < v.node->mNumMeshes; ++i)
            placements[v.node->mMeshes[i]].push_back(v.world);
        for (unsigned c = 0; c < v.node->mNumChildren; ++c)
            stack.push_back(
                {v.node->mChildren[c], v.world * toMat4(v.node->mChildren[c]->mTransformation)});
    }

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
        mesh.positions.reserve(3 * am->mNumVertices + 1);
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            Vec3 p(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
            if (bake) p = xf.point(p);
            mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
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
            for (const Mat4& m : placements[mi])
                scene.instances.push_back(Instance::place(meshIndex, m));
    }

    if (extras) return;  // COLLADA lights and camera come from the CGL pass

    for (unsigned i = 0; i < as->mNumLights; ++i) {
        const aiLight* al = as->mLights[i];
        auto it = nodeWorld.find(al->mName.C_Str());
        Mat4 world = it == nodeWorld.end() ? Mat4::identity() : it->second;
        Light l;
        l.name = al->mName.C_Str();
        l.radiance = Color(al->mColorDiffuse.r, al->mColorDiffuse.g, al->mColorDiffuse.b);
        l.position = world.point(Vec3(al->mPosition.x, al->mPosition.y, al->mPosition.z));
        Vec3 dir = world.vector(Vec3(al->mDirection.x, al->mDirection.y, al->mDirection.z));
        if (length(dir) > 0) l.direction = normalize(dir);
        switch (al->mType) {
            case aiLightSource_POINT:
                l.kind = LightKind::Point;
                break;
            case aiLightSource_SPOT:
                l.kind = LightKind::Spot;
                l.spotInnerDeg = degrees(al->mAngleInnerCone);
                l.spotOuterDeg = degrees(al->mAngleOuterCone);
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
                Vec3 up = world.vector(Vec3(al->mUp.x, al->mUp.y, al->mUp.z));
                Vec3 side = normalize(cross(l.direction, up));
                l.dimX = side * al->mSize.x;
                l.dimY = normalize(up) * al->mSize.y;
                break;
            }
            default:
                continue;
        }
        scene.lights.push_back(l);
    }
    if (as->mNumCameras > 0) {
        const aiCamera* ac = as->mCameras[0];
        auto it = nodeWorld.find(ac->mName.C_Str());
        Mat4 world = it == nodeWorld.end() ? Mat4::identity() : it->second;
        Camera& cam = scene.camera;
        cam.position = world.point(Vec3(ac->mPosition.x, ac->mPosition.y, ac->mPosition.z));
        cam.forward = normalize(world.vector(Vec3(ac->mLookAt.x, ac->mLookAt.y, ac->mLookAt.z)));
        cam.up = normalize(world.vector(Vec3(ac->mUp.x, ac->mUp.y, ac->mUp.z)));
        // Assimp documents mHorizontalFOV as the half angle.
        cam.hFovDeg = std::min(170.0f, 2.0f * degrees(ac->mHorizontalFOV));
        float aspect = ac->mAspect > 0 ? ac->mAspect : 4.0f / 3.0f;
        cam.vFovDeg = degrees(2.0f * std::atan(std::tan(radians(0.5f * cam.hFovDeg)) / aspect));
        if (ac->mClipPlaneNear > 0) cam.nearClip = ac->mClipPlaneNear;
        if (ac->mClipPlaneFar > cam.nearClip) cam.farClip = ac->mClipPlaneFar;
        cam.fromFile = true;
        scene.hasFileCamera = true;
    }
}

}  // namespace kiln
