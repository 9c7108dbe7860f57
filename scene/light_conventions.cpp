// Light units and falloff as each format defines them, for the lights Assimp hands over
// (docs/import.md, "Light conventions"). kiln's lights are physical: a point light of intensity I
// gives irradiance I / d^2 (or I / (c + l d + q d^2) where a file states its attenuation), a
// Lambertian surface reflects albedo / pi of the irradiance. Authoring tools that shade without
// the 1 / pi (Blender Internal, 3ds Max's scanline renderer, COLLADA's common profile) show a white
// surface facing a light of "intensity 1" at full brightness: their intensity is pi times kiln's.
#include <assimp/light.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "scene/importers.h"

namespace kiln {
namespace {

// *LIGHTOBJECT blocks of an ASE file: each light's node name, type and cone.
std::map<std::string, AseLight> readAseLights(const std::string& path) {
    std::map<std::string, AseLight> lights;
    std::ifstream in(path);
    std::string line;
    int depth = 0, lightDepth = -1;
    AseLight current;
    std::string name;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string key;
        words >> key;
        if (key == "*LIGHTOBJECT") lightDepth = depth, current = AseLight{}, name.clear();
        if (lightDepth >= 0) {
            if (key == "*NODE_NAME" && name.empty()) {
                size_t open = line.find('"'), close = line.rfind('"');
                if (open != std::string::npos && close > open)
                    name = line.substr(open + 1, close - open - 1);
            } else if (key == "*LIGHT_TYPE") {
                words >> current.type;
            } else if (key == "*LIGHT_HOTSPOT") {
                words >> current.hotspot;
            } else if (key == "*LIGHT_FALLOFF") {
                words >> current.falloff;
            }
        }
        for (char c : line) depth += c == '{' ? 1 : c == '}' ? -1 : 0;
        if (lightDepth >= 0 && depth <= lightDepth) {
            if (!name.empty()) lights[name] = current;
            lightDepth = -1;
        }
    }
    return lights;
}

bool looksLikeCollada(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(4096, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    return head.find("<COLLADA") != std::string::npos;
}

// Blender Internal (2.4x-2.7x) shades a Lambert surface as colour * energy * visibility * N.L
// (render/intern/source/shadeoutput.c, lamp_get_visibility), with the visibility of the lamp's
// falloff type and Distance D: constant 1, inverse linear D / (D + d), inverse square
// D / (D + d^2) (Blender's own formula, not D^2 / (D^2 + d^2)), sliders
// D / (D + att1 d) * D^2 / (D^2 + att2 d^2). An area lamp gives energy * 2 pi * F * D^2 / A
// (area_lamp_energy: F the rectangle's form factor, A its area). Blender 2.80 and later (Cycles,
// Eevee) state watts: a point or spot light of power P has intensity P / (4 pi), a sun's strength
// is irradiance.
bool convertBlenderLamp(const BlendLamp& b, int version, const std::string& path, Light& l,
                        Scene& scene) {
    const Color colour = Color(b.r, b.g, b.b) * b.energy;
    const std::string name = "Blender lamp '" + l.name + "'";
    if (version >= 280) {
        if (l.kind == LightKind::Point || l.kind == LightKind::Spot) {
            l.radiance = colour * (1.0f / (4.0f * kPi));
        } else if (l.kind == LightKind::Area) {
            float area = b.areaSize * (b.areaShape == 1 ? b.areaSizeY : b.areaSize);
            if (area > 0) l.radiance = colour * (1.0f / (kPi * area));
            scene.warnings.push_back(name +
                                     ": an area light's power is converted as a "
                                     "Lambertian emitter's (radiance = power / (pi area)); "
                                     "Cycles' own scale may differ");
        }
        if (l.kind == LightKind::Spot) {  // radians, the full cone
            l.spotOuterDeg = 0.5f * degrees(b.spotSize);
            l.spotInnerDeg = l.spotOuterDeg * (1.0f - b.spotBlend);
        }
        return true;
    }
    if (b.mode & 16) {
        scene.warnings.push_back(name +
                                 " is a negative lamp (it removes light in Blender "
                                 "Internal): kiln cannot, and drops it");
        return false;
    }
    std::vector<std::string> inexact;
    if (l.kind == LightKind::Point || l.kind == LightKind::Spot) {
        l.radiance = colour * kPi;
        l.attenuationStated = true;
        l.attenuationConstant = 1, l.attenuationLinear = 0, l.attenuationQuadratic = 0;
        const float d = b.dist > 0 ? b.dist : 0;
        int falloff = b.falloffType;
        if (falloff < 0) falloff = (b.mode & 8) ? 4 : 1;  // before 2.46: the Quad switch
        if (d > 0) switch (falloff) {
                case 1:  // inverse linear
                    l.attenuationLinear = 1 / d;
                    break;
                case 3:  // custom curve
                    inexact.push_back("its custom falloff curve is taken as inverse square");
                    [[fallthrough]];
                case 2:  // inverse square, Blender's D / (D + d^2)
                    l.attenuationQuadratic = 1 / d;
                    break;
                case 4:  // Lin/Quad sliders
                    l.attenuationLinear = b.att1 / d;
                    l.attenuationQuadratic = b.att2 / (d * d);
                    if (b.att1 > 0 && b.att2 > 0)
                        inexact.push_back(
                            "its two falloff sliders multiply (a cubic term kiln drops)");
                    break;
                default:  // constant
                    break;
            }
        if (b.mode & 64)
            inexact.push_back("its Sphere option (no light beyond the Distance) is not applied");
        if (l.kind == LightKind::Spot) {  // the full cone, in degrees before Blender 2.70
            float full = version < 270 ? b.spotSize : degrees(b.spotSize);
            l.spotOuterDeg = 0.5f * full;
            // Blender blends in cosine: from cos(outer) to cos(outer) + (1 - cos(outer)) * blend.
            float cosOuter = std::cos(radians(l.spotOuterDeg));
            float cosInner = std::min(1.0f, cosOuter + (1 - cosOuter) * b.spotBlend);
            l.spotInnerDeg = degrees(std::acos(cosInner));
        }
    } else if (l.kind == LightKind::Directional) {
        l.radiance = colour * kPi;
    } else if (l.kind == LightKind::Area) {
        float area = b.areaSize * (b.areaShape == 1 ? b.areaSizeY : b.areaSize);
        if (area > 0 && b.dist > 0) l.radiance = colour * (2 * kPi * b.dist * b.dist / area);
        if (std::abs(b.gamma - 1) > 1e-6f)
            inexact.push_back("its gamma " + std::to_string(b.gamma) + " is taken as 1");
    }
    if (!inexact.empty()) {
        std::string text = name + " (Blender Internal) is converted approximately: ";
        for (size_t i = 0; i < inexact.size(); ++i) text += (i ? "; " : "") + inexact[i];
        scene.warnings.push_back(text);
    }
    (void)path;
    return true;
}

}  // namespace

LightConventions lightConventionsOf(const std::string& path) {
    LightConventions c;
    std::string ext = lowerExtension(path);
    if (ext == ".blend") {
        c.format = LightConventions::Format::Blender;
        c.blend = readBlendLamps(path, c.reason);
    } else if (ext == ".ase" || ext == ".ask") {
        c.format = LightConventions::Format::Ase;
        c.ase = readAseLights(path);
    } else if (ext != ".dae" && looksLikeCollada(path)) {
        c.format = LightConventions::Format::Collada;
    }
    return c;
}

bool convertLightUnits(const std::string& path, const LightConventions& c, const aiLight* al,
                       Light& l, Scene& scene) {
    using Format = LightConventions::Format;
    if (c.format == Format::Blender) {
        if (!c.blend) {
            scene.warnings.push_back("Blender lamp '" + l.name +
                                     "': the file's lamp data could "
                                     "not be read (" +
                                     c.reason +
                                     "); kept as Assimp gives it, "
                                     "intensity energy with 1 / d^2");
            return true;
        }
        for (const BlendLamp& b : c.blend->lamps)
            if (b.object == l.name) return convertBlenderLamp(b, c.blend->version, path, l, scene);
        scene.warnings.push_back(
            "Blender lamp '" + l.name +
            "': no lamp object of that name in "
            "the file; kept as Assimp gives it, intensity energy with 1 / d^2");
        return true;
    }
    if (c.format == Format::Ase) {
        // 3ds Max's scanline renderer shades like Blender Internal (no 1 / pi); ASE carries no
        // decay, and Max's default is none. A "Free" light without a cone (hotspot and falloff 0)
        // is the Skylight, a sky dome: kiln's sky light from above of its colour.
        auto it = c.ase.find(l.name);
        if (it != c.ase.end() && it->second.type == "Free" && it->second.hotspot == 0 &&
            it->second.falloff == 0) {
            l.kind = LightKind::Ambient;
            l.direction = Vec3(0, 1, 0);
            scene.warnings.push_back("ASE light '" + l.name +
                                     "' is a 3ds Max Skylight (a 'Free' light without a cone): "
                                     "lit as a sky of its colour from above");
            return true;
        }
        if (l.kind == LightKind::Point || l.kind == LightKind::Spot) {
            l.attenuationStated = true;
            l.attenuationConstant = 1, l.attenuationLinear = 0, l.attenuationQuadratic = 0;
        }
        if (l.kind != LightKind::Ambient) l.radiance = l.radiance * kPi;
        return true;
    }
    // COLLADA read by Assimp alone (not .dae): the common profile, as the CGL pass converts it
    // (cgl_extras.cpp, commonProfileUnits).
    if (l.kind == LightKind::Ambient) {
        scene.warnings.push_back("light '" + l.name +
                                 "': a COLLADA ambient light scales each material's ambient "
                                 "colour; kiln lights the scene with a sky of its colour from "
                                 "above instead");
        return true;
    }
    l.radiance = l.radiance * kPi;
    if (l.kind == LightKind::Point || l.kind == LightKind::Spot) {
        float cst = al->mAttenuationConstant, lin = al->mAttenuationLinear,
              quad = al->mAttenuationQuadratic;
        l.attenuationStated = true;
        bool usable = cst >= 0 && lin >= 0 && quad >= 0 && cst + lin + quad > 0;
        l.attenuationConstant = usable ? cst : 1;
        l.attenuationLinear = usable ? lin : 0;
        l.attenuationQuadratic = usable ? quad : 0;
    }
    return true;
}

}  // namespace kiln
