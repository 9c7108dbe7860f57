// Opens the textures importers found, at load time, so an unreadable one is a warning before any
// rendering starts and the material falls back to its plain colour instead of failing mid-render.
#include "scene/mesh_maps.h"
#include "scene/scene_loader.h"

namespace kiln {

void openTextures(Scene& scene, float cacheMb) {
    if (scene.textureSources.empty()) return;
    auto set = std::make_shared<TextureSet>(cacheMb);
    std::vector<int> idOf(scene.textureSources.size(), -1);
    for (size_t i = 0; i < scene.textureSources.size(); ++i) {
        const TextureSource& source = scene.textureSources[i];
        std::string note;
        try {
            idOf[i] = set->add(source, &note);
        } catch (const ImageReadError& e) {
            scene.warnings.push_back("texture " + std::string(e.what()) +
                                     "; its materials render untextured");
        }
        if (!note.empty()) scene.warnings.push_back("texture " + source.name + ": " + note);
    }
    auto remap = [&](int& id) {
        if (id >= 0) id = idOf[size_t(id)];
    };
    for (Material& m : scene.materials)
        for (int* id : textureIds(m)) remap(*id);
    scene.textures = std::move(set);
}

}  // namespace kiln
