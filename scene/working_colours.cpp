#include "scene/working_colours.h"

#include "color/working_space.h"

namespace kiln {

void convertColoursToWorkingSpace(Scene& scene) {
    const WorkingSpace& space = workingSpace();
    if (space.rec709) return;
    auto convert = [&](Color& c) { c = fromRec709(space, c); };
    // A conductor's eta and k are optical constants sampled at three wavelengths, not colours.
    for (Material& m : scene.materials)
        for (Color* c : {&m.albedo, &m.reflectance, &m.transmittance, &m.emission}) convert(*c);
    // An environment light's radiance is its (grey) scale; its map is in the working space.
    for (Light& l : scene.lights)
        if (l.kind != LightKind::Environment) convert(l.radiance);
    for (TriangleMesh& mesh : scene.meshes) {
        if (mesh.colorsInWorkingSpace) continue;
        for (size_t i = 0; i + 2 < mesh.colors.size(); i += 3) {
            Color c =
                fromRec709(space, Color(mesh.colors[i], mesh.colors[i + 1], mesh.colors[i + 2]));
            mesh.colors[i] = c.x, mesh.colors[i + 1] = c.y, mesh.colors[i + 2] = c.z;
        }
    }
}

}  // namespace kiln
