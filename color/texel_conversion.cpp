#include "color/texel_conversion.h"

#include "color/srgb_decode.h"
#include "color/working_space.h"

namespace kiln {

void TexelConversion::apply(float* texels, size_t count, int channels) const {
    if (decodeSrgb) decodeSrgbTexels(texels, count, channels);
    if (!matrix || channels < 3) return;
    for (size_t i = 0; i < count; ++i) {
        float* p = texels + i * size_t(channels);
        Color c = applyMatrix(toWorking, Color(p[0], p[1], p[2]));
        p[0] = c.x, p[1] = c.y, p[2] = c.z;
    }
}

TexelConversion linearConversion(const Chromaticities* stated) {
    TexelConversion conversion;
    const WorkingSpace& space = workingSpace();
    bool statedRec709 = !stated || sameChromaticities(*stated, kRec709D65);
    if (statedRec709 && space.rec709) return conversion;
    Mat3 toRec709 = statedRec709 ? conversion.toWorking : toWorkingSpace(*stated);
    conversion.toWorking = space.rec709 ? toRec709 : multiply(space.fromRec709, toRec709);
    conversion.matrix = true;
    return conversion;
}

TexelConversion imageConversion(bool srgbEncoded, const Chromaticities* stated) {
    if (!srgbEncoded) return linearConversion(stated);
    TexelConversion decode;
    decode.decodeSrgb = true;
    return decode;
}

}  // namespace kiln
