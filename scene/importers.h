// Format readers. Each fills a Scene in world space (Y up) and throws SceneError on bad input.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/memory.h"
#include "scene/cgl_extras.h"
#include "scene/scene.h"

struct aiScene;
struct aiMaterial;
struct aiLight;

namespace kiln {

// Any format Assimp reads. With extras (COLLADA), materials, lights, spheres and the camera come
// from the CGL pass and the course's up-axis convention replaces Assimp's.
void importWithAssimp(const std::string& path, const ColladaExtras* extras, Scene& scene);

// One warning naming every glTF extension the file uses that neither Assimp nor kiln reads.
void warnUnreadGltfExtensions(const std::string& path, Scene& scene);
// What a glTF material states in the extensions Assimp 5.2 does not hand over:
// KHR_materials_emissive_strength (1 where it states none; AI_MATKEY_EMISSIVE_INTENSITY stays
// unset) and KHR_materials_specular (its factor and colour; its textures are not read).
struct GltfMaterialExtras {
    float emissiveStrength = 1;
    std::optional<float> specular;
    std::optional<Color> specularColour;
    std::vector<std::string> unreadTextures;
};
// Each glTF material's, in the file's order, which is Assimp's (its default material comes after
// them); empty when unreadable.
std::vector<GltfMaterialExtras> gltfMaterialExtras(const std::string& path);

// An Assimp material's base-colour texture as a source of the scene (Material::albedoTexture; the
// albedo becomes 1 unless the file states a colour, which then multiplies it), and a warning for
// every texture slot kiln ignores.
void readAssimpTextures(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                        bool statesColour, Material& m, Scene& scene);

// Maps of an Assimp material (scene/assimp_maps.cpp): the normal map and its scale, alpha (glTF
// alphaMode and cutoff, base-colour alpha; OBJ d and map_d) into Material::maps.
void readAssimpMaps(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                    Material& m, Scene& scene);
// Whether the material's Assimp texture slot (an aiTextureType) is one kiln reads, or warns about
// itself, for this material and format (readAssimpMaps): the slots left over get a warning each.
bool readsTextureSlot(unsigned slot, const Material& m, const std::string& assetPath);
// The slot's wrap modes (glTF sampler wrapS/wrapT, as Assimp's mapping modes) into uv.wrap, and
// its UV transform (KHR_texture_transform through Assimp) if the material states one (true).
bool readUvTransform(const aiMaterial* am, unsigned slot, const std::string& assetPath,
                     UvTransform& uv);
// The texture source an Assimp texture reference names (a file relative to the asset, or bytes
// embedded in it), or false and the reason; and its index in Scene::textureSources (once per file).
bool assimpTextureSource(const aiScene* as, const std::string& assetPath, const std::string& ref,
                         TextureSource& source, std::string& reason);
int addTextureSource(Scene& scene, TextureSource&& source);

// Makes m principled (base colour, metallic, roughness, specular, clearcoat, transmission, volume,
// sheen; glTF: the ior) when the Assimp material states a glTF base colour or a metallic factor;
// false, m unchanged, otherwise.
bool readPrincipled(const aiMaterial* am, bool gltf, Material& m);
// Whether the material states a glTF base colour or a metallic factor (readPrincipled's test).
bool statesMetallicRoughness(const aiMaterial* am);

// A Phong material with a specular colour as Blender's importers make it, so that it shows the
// highlight Cycles shows: a principled dielectric (base colour: the diffuse colour) whose specular
// layer reflects F0 = 0.08 Ks per channel. Blender's Specular input s (OBJ: the mean of Ks; FBX:
// 2 SpecularFactor) is F0 0.08 s, so kiln's glTF-style specular factor is 2 s and Ks / mean(Ks)
// its KHR_materials_specular tint; roughness is 1 - sqrt(Ns / 1000) (OBJ) or
// 1 - sqrt(Shininess / 100) (FBX), Blender's conversions. False, m unchanged, without a specular
// colour (or a black one) or for other formats (their Phong rules differ: a warning names it).
enum class PhongDialect { None, Obj, Fbx };
bool readPhongSpecular(const aiMaterial* am, PhongDialect dialect, Material& m);

// A warning for each feature of an Assimp material that kiln's rendering of it drops (gloss and
// specular colour of Phong materials, opacity, transmission, clearcoat of a non-principled one).
void warnDroppedMaterialFeatures(const aiMaterial* am, const Material& m, Scene& scene);

// A 3DS camera as its editor chunk (0x4700) states it, in the file's Z-up coordinates.
struct Camera3ds {
    Vec3 position, target;
    float bankDeg = 0, lensMm = 0;
};
// The camera of the named object, if the file has one.
std::optional<Camera3ds> read3dsCamera(const std::string& path, const std::string& name);
// Its horizontal field of view in degrees.
float fovFrom3dsLens(float lensMm);

// The file name's extension, lower case, with its dot ("" when it has none).
std::string lowerExtension(const std::string& path);

// Any supported file into `scene` (appending), without validation or completion (lights, framing).
void importFile(const std::string& path, Scene& scene);
// importFile's first checks (there, not a folder, readable, not empty): SceneError naming path.
void checkSceneFileOpens(const std::string& path);

// kiln's own scene description (.kiln, XML): includes other scene files, places meshes by path with
// a transform or a fit to a box, instances a mesh on a grid, and sets materials, lights and the
// camera.
void readKilnScene(const std::string& path, Scene& scene);
// Its every element checked, and those of the .kiln files it includes, importing nothing: a mistake
// anywhere in a tree of .kiln files is refused before its first mesh is read.
void checkKilnScene(const std::string& path);
// True where the .kiln file certainly has no material named `name` ("": none at all): none of its
// <material> elements, and no part whose import could bring one.
bool kilnSceneLacksMaterial(const std::string& path, const std::string& name);

// Throws SceneError, before any allocation, when a mesh of these counts would not fit.
void checkMemoryFor(const std::string& path, uint64_t vertices, uint64_t triangles);

// Direct binary/ASCII PLY reader: face lists and tristrips (which Assimp 5.2 reads as one
// triangle).
void readPly(const std::string& path, Scene& scene);

// A lamp of a .blend file as Blender stores it (scene/blend_lamps.cpp), named after its object
// (Assimp names its aiLight so). type: 0 point ("Local"), 1 sun, 2 spot, 3 hemi, 4 area.
// falloffType: 0 constant, 1 inverse linear, 2 inverse square, 3 curve, 4 sliders (-1: the file
// predates the field). mode: flags (16 negative, 64 sphere). spotSize: degrees before Blender
// 2.70, radians after; the full cone angle.
struct BlendLamp {
    std::string object;
    int type = 0, mode = 0, falloffType = -1, areaShape = 0;
    float r = 1, g = 1, b = 1, energy = 1, dist = 25, att1 = 0, att2 = 1, gamma = 1;
    float spotSize = 0, spotBlend = 0, areaSize = 0, areaSizeY = 0;
};
struct BlendLamps {
    int version = 0;  // Blender's version that wrote the file: 248 for 2.48
    std::vector<BlendLamp> lamps;
};
// The file's lamps, or nothing (and why) when the file cannot be read this way.
std::optional<BlendLamps> readBlendLamps(const std::string& path, std::string& reason);

// An ASE light as the file states it (Assimp keeps no cone for a "Free" light).
struct AseLight {
    std::string type;  // Omni, Target, Free, Directional, TargetDirectional
    float hotspot = -1, falloff = -1;
};

// What kiln knows of a file's lights beyond Assimp's aiLight, to convert them to kiln's units as
// the format defines them (scene/light_conventions.cpp, docs/import.md "Light conventions").
struct LightConventions {
    enum class Format { Other, Blender, Ase, Collada } format = Format::Other;
    std::optional<BlendLamps> blend;      // Blender: the lamps as the file stores them
    std::string reason;                   // why they could not be read
    std::map<std::string, AseLight> ase;  // ASE: by node name
};
LightConventions lightConventionsOf(const std::string& path);
// Converts l (kind, position and direction from the aiLight, radiance Assimp's colour) to kiln's
// units as the file's format defines them, warning where that cannot be exact; false when the
// light is to be dropped (warned). For formats other than Blender, ASE and COLLADA read by Assimp
// alone, the caller's rules apply.
bool convertLightUnits(const std::string& path, const LightConventions& c, const aiLight* al,
                       Light& l, Scene& scene);

// Direct multi-threaded OBJ reader for geometry-only files. Returns false, leaving `scene`
// untouched, when the file needs Assimp (materials, free-form geometry, attribute indices that
// differ from position indices).
bool readObj(const std::string& path, Scene& scene);

// Every index of every 'f', 'l' and 'p' statement of an OBJ file checked against the file's own
// counts of 'v', 'vt' and 'vn' (negative indices against those defined before the statement):
// throws SceneError naming the line, the index and the count. Run before Assimp reads a file
// kiln's reader declined: Assimp 5.2 renders a face whose normal index is past the last 'vn' with
// some other normal, and says nothing.
void checkObjIndices(const std::string& path);

}  // namespace kiln
