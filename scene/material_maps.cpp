#include "scene/material_maps.h"

#include <cmath>

namespace kiln {

UvTransform UvTransform::gltf(float offsetU, float offsetV, float rotation, float scaleU,
                              float scaleV) {
    // glTF UV g = (u, 1 - v); g' = T R S g with R = [cos sin; -sin cos] (the direction the
    // Khronos TextureTransformTest asset checks, and three.js applies); the lookup reads g'.
    float c = std::cos(rotation), s = std::sin(rotation);
    UvTransform x;
    x.a = c * scaleU, x.b = -s * scaleV, x.c = offsetU + s * scaleV;
    x.d = -s * scaleU, x.e = -c * scaleV, x.f = offsetV + c * scaleV;
    return x;
}

UvTransform UvTransform::assimp(float translateU, float translateV, float rotation, float scaleU,
                                float scaleV) {
    // Assimp's aiUVTransform (its TransformUVCoords step), in its UV space (v up): uv' = C + S R
    // (uv + T - C) about the centre C = (0.5, 0.5); the lookup reads s = u', t = 1 - v'.
    float c = std::cos(rotation), s = std::sin(rotation);
    float pu = translateU - 0.5f, pv = translateV - 0.5f;
    UvTransform x;
    x.a = scaleU * c, x.b = -scaleU * s, x.c = 0.5f + scaleU * (c * pu - s * pv);
    x.d = -scaleV * s, x.e = -scaleV * c, x.f = 0.5f - scaleV * (s * pu + c * pv);
    return x;
}

const char* toString(AlphaMode mode) {
    switch (mode) {
        case AlphaMode::Opaque:
            return "opaque";
        case AlphaMode::Mask:
            return "mask";
        case AlphaMode::Blend:
            return "blend";
    }
    return "unknown";
}

}  // namespace kiln
