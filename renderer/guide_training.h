// The guide field's training (integrators/guiding.h), before a render's first pixel: a fixed number
// of caustic photons with a seed of their own, traced in batches whose records are joined in a
// fixed order. The field depends on the scene and the render's seed alone, not on the image region,
// samples, shard or thread count, so every shard and resumed render learns the same field bit for
// bit, and the training never shares random numbers with the render it guides.
#pragma once

#include <memory>
#include <string>

#include "integrators/path.h"
#include "renderer/render_loop.h"

namespace kiln {

struct GuideTraining {
    // Photons traced (2^17-2^19 measured alike on the chrome bunny; 2^18 take 0.04 s on 2 cores).
    static constexpr size_t kPhotons = size_t(1) << 18;
    // Landed photons per region: fewer give finer regions but fewer cones each (16 measured worse,
    // 64 and 128 no better).
    static constexpr size_t kLeafRecords = 32;
    // "on: N photons, R landed caustics, L regions" for the EXR header and checkpoint fingerprints.
    static std::string describe(const GuideField& field);
};

// Trains a field for the integrator (as set up for this render, unguided).
std::shared_ptr<const GuideField> trainGuide(const PathIntegrator& integrator,
                                             const RenderSettings& settings);

}  // namespace kiln
