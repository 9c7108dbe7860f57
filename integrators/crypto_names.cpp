#include "integrators/crypto_names.h"

#include "renderer/film/cryptomatte.h"

namespace kiln {
namespace {

std::string nameOr(const std::string& name, const char* kind, size_t index) {
    return name.empty() ? kind + std::to_string(index) : name;
}

std::vector<uint32_t> idsOf(const std::vector<std::string>& names) {
    std::vector<uint32_t> ids;
    ids.reserve(names.size());
    for (const std::string& n : names) ids.push_back(cryptoIdBits(n));
    return ids;
}

}  // namespace

CryptoNames::CryptoNames(const Scene& scene) {
    // Objects by the scene node that places them (as Cycles and Arnold), else by the mesh.
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        meshes.push_back(nameOr(mesh.node.empty() ? mesh.name : mesh.node, "mesh", m));
    }
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        instances.push_back(!inst.node.empty() ? inst.node
                                               : meshes[inst.mesh] + "#" + std::to_string(i));
    }
    for (size_t s = 0; s < scene.spheres.size(); ++s)
        spheres.push_back(nameOr(scene.spheres[s].name, "sphere", s));
    for (size_t m = 0; m < scene.materials.size(); ++m)
        materials.push_back(nameOr(scene.materials[m].name, "material", m));
}

std::vector<std::string> CryptoNames::objects(const Scene& scene) const {
    std::vector<bool> prototype = scene.prototypeMask();
    std::vector<std::string> all;
    for (size_t m = 0; m < meshes.size(); ++m)
        if (!prototype[m]) all.push_back(meshes[m]);
    all.insert(all.end(), instances.begin(), instances.end());
    all.insert(all.end(), spheres.begin(), spheres.end());
    return all;
}

CryptoIds::CryptoIds(const Scene& scene) {
    CryptoNames names(scene);
    meshes_ = idsOf(names.meshes);
    instances_ = idsOf(names.instances);
    spheres_ = idsOf(names.spheres);
    materials_ = idsOf(names.materials);
}

uint32_t CryptoIds::object(const Hit& hit) const {
    if (hit.instance != kInvalidId) return instances_[hit.instance];
    if (hit.shape == kSphereShape) return spheres_[hit.prim];
    return meshes_[hit.shape];
}

}  // namespace kiln
