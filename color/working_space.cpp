#include "color/working_space.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "color/color_config.h"
#include "color/ocio_configs.h"

namespace kiln {
namespace OCIO = OCIO_NAMESPACE;

namespace {

// Rec.709 primaries to CIE XYZ, D65 white (IEC 61966-2-1), rows X Y Z.
constexpr Mat3 kRec709ToXyz = {{{0.4123908, 0.3575843, 0.1804808},
                                {0.2126390, 0.7151687, 0.0721923},
                                {0.0193308, 0.1191948, 0.9505322}}};

// xy of the primaries (the matrix's columns) and of the white (their sum).
Chromaticities chromaticitiesOf(const Mat3& xyz) {
    Chromaticities c{};
    auto xy = [&](double X, double Y, double Z, size_t at) {
        c[at] = float(X / (X + Y + Z)), c[at + 1] = float(Y / (X + Y + Z));
    };
    for (size_t i = 0; i < 3; ++i) xy(xyz[0][i], xyz[1][i], xyz[2][i], 2 * i);
    xy(xyz[0][0] + xyz[0][1] + xyz[0][2], xyz[1][0] + xyz[1][1] + xyz[1][2],
       xyz[2][0] + xyz[2][1] + xyz[2][2], 6);
    return c;
}

// ACES2065-1 (AP0) to XYZ at its own D60 white (SMPTE ST 2065-1), unadapted.
constexpr Mat3 kAp0ToXyz = {{{0.9525523959, 0.0, 0.0000936786},
                             {0.3439664498, 0.7281660966, -0.0721325464},
                             {0.0, 0.0, 1.0088251844}}};

// The matrix of an RGB -> RGB processor, from the images of the unit vectors.
Mat3 matrixOf(const OCIO::ConstProcessorRcPtr& processor) {
    OCIO::ConstCPUProcessorRcPtr cpu = processor->getDefaultCPUProcessor();
    Mat3 m;
    for (size_t c = 0; c < 3; ++c) {
        float rgb[3] = {0, 0, 0};
        rgb[c] = 1;
        cpu->applyRGB(rgb);
        for (size_t r = 0; r < 3; ++r) m[r][c] = rgb[r];
    }
    return m;
}

// The config's scene_linear -> XYZ D65 of the three primaries, through whichever interchange
// role it has; false when it has none.
bool primariesToXyz(const OCIO::ConstConfigRcPtr& config, const std::string& sceneLinear,
                    Mat3& xyz) {
    OCIO::ConstProcessorRcPtr processor;
    if (config->getColorSpace("cie_xyz_d65_interchange")) {
        processor = config->getProcessor(sceneLinear.c_str(), "cie_xyz_d65_interchange");
    } else if (config->getColorSpace("aces_interchange")) {
        auto group = OCIO::GroupTransform::Create();
        auto toAces = OCIO::ColorSpaceTransform::Create();
        toAces->setSrc(sceneLinear.c_str());
        toAces->setDst("aces_interchange");
        auto toXyz = OCIO::BuiltinTransform::Create();
        toXyz->setStyle("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD");
        group->appendTransform(toAces);
        group->appendTransform(toXyz);
        processor = config->getProcessor(group);
    } else {
        return false;
    }
    xyz = matrixOf(processor);
    return true;
}

// The chromaticities a file states: through ACES2065-1 the space's own white (ACEScg: D60), else
// as adapted to D65.
Chromaticities statedChromaticities(const OCIO::ConstConfigRcPtr& config,
                                    const std::string& sceneLinear, const Mat3& xyzD65) {
    if (!config->getColorSpace("aces_interchange")) return chromaticitiesOf(xyzD65);
    Mat3 toAp0 = matrixOf(config->getProcessor(sceneLinear.c_str(), "aces_interchange"));
    return chromaticitiesOf(multiply(kAp0ToXyz, toAp0));
}

WorkingSpace describe(const std::string& path) {
    WorkingSpace space;
    try {
        OCIO::ConstConfigRcPtr config = sharedOcioConfig(path);
        for (const char* role : {"scene_linear", "linear"})
            if (OCIO::ConstColorSpaceRcPtr cs = config->getColorSpace(role)) {
                space.name = cs->getName();
                break;
            }
        Mat3 xyz;
        if (space.name.empty() || !primariesToXyz(config, space.name, xyz)) return space;
        space.known = true;
        for (size_t r = 0; r < 3; ++r)
            for (size_t c = 0; c < 3; ++c)
                space.offFromRec709 =
                    std::max(space.offFromRec709, std::abs(xyz[r][c] - kRec709ToXyz[r][c]));
        // 2e-3 admits the chromatic adaptations configs use between D60 and D65.
        space.rec709 = space.offFromRec709 <= 2e-3;
        if (space.rec709) return space;
        space.fromRec709 = multiply(inverse(xyz), kRec709ToXyz);
        space.chromaticities = statedChromaticities(config, space.name, xyz);
    } catch (const OCIO::Exception& e) {
        throw std::invalid_argument(path + ": OCIO config unusable: " + e.what());
    }
    return space;
}

}  // namespace

const WorkingSpace& workingSpace() {
    static std::mutex mutex;
    // By the config's read ($OCIO may change between scenes, a long session may edit the config);
    // never erased: callers keep the reference.
    static std::map<std::string, WorkingSpace> made;
    const std::string path = colorConfigPath(), stamp = ocioConfigStamp(path);
    std::lock_guard lock(mutex);
    auto it = made.find(stamp);
    if (it == made.end()) it = made.emplace(stamp, describe(path)).first;
    return it->second;
}

Color fromRec709(const WorkingSpace& space, const Color& c) {
    return space.rec709 ? c : applyMatrix(space.fromRec709, c);
}

}  // namespace kiln
