// What the EXR states about the scene beside the film: OpenEXR's camera matrices and the
// Cryptomatte manifests. kiln render and the tests fill ExrOptions through this one place.
#pragma once

#include "color/image_output.h"
#include "renderer/render_loop.h"
#include "scene/scene.h"

namespace kiln {

// The camera as RenderSettings frames it (fitted field of view), in world coordinates.
ExrCamera exrCamera(const Scene& scene, const RenderSettings& settings);

void addSceneToExr(ExrOptions& options, const Scene& scene, const RenderSettings& settings,
                   const AovRequest& aovs);

}  // namespace kiln
