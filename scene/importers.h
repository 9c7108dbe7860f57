// Format readers. Each fills a Scene in world space (Y up) and throws SceneError on bad input.
#pragma once

#include <string>

#include "renderer/core/memory.h"
#include "scene/cgl_extras.h"
#include "scene/scene.h"

struct aiScene;
struct aiMaterial;

namespace kiln {

// Any format Assimp reads. With extras (COLLADA), materials, lights, spheres and the camera come
// from the CGL pass and the course's up-axis convention replaces Assimp's.
void importWithAssimp(const std::string& path, const ColladaExtras* extras, Scene& scene);

// An Assimp material's base-colour texture as a source of the scene (Material::albedoTexture; the
// albedo becomes 1 unless the file states a colour, which then multiplies it), and a warning for
// every texture slot kiln ignores.
void readAssimpTextures(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                        bool statesColour, Material& m, Scene& scene);

// Makes m principled (base colour, metallic, roughness, specular, clearcoat) when the Assimp
// material states a glTF base colour or a metallic factor; false, m unchanged, otherwise.
bool readPrincipled(const aiMaterial* am, Material& m);

// A warning for each feature of an Assimp material that kiln's rendering of it drops (gloss and
// specular colour of Phong materials, opacity, transmission, clearcoat of a non-principled one).
void warnDroppedMaterialFeatures(const aiMaterial* am, const Material& m, Scene& scene);

// The file name's extension, lower case, with its dot ("" when it has none).
std::string lowerExtension(const std::string& path);

// Any supported file into `scene` (appending), without validation or completion (lights, framing).
void importFile(const std::string& path, Scene& scene);

// kiln's own scene description (.kiln, XML): includes other scene files, places meshes by path with
// a transform or a fit to a box, instances a mesh on a grid, and sets materials, lights and the
// camera.
void readKilnScene(const std::string& path, Scene& scene);

// Throws SceneError, before any allocation, when a mesh of these counts would not fit.
void checkMemoryFor(const std::string& path, uint64_t vertices, uint64_t triangles);

// Direct binary/ASCII PLY reader: face lists and tristrips (which Assimp 5.2 reads as one
// triangle).
void readPly(const std::string& path, Scene& scene);

// Direct multi-threaded OBJ reader for geometry-only files. Returns false, leaving `scene`
// untouched, when the file needs Assimp (materials, free-form geometry, attribute indices that
// differ from position indices).
bool readObj(const std::string& path, Scene& scene);

}  // namespace kiln
