// The CS184 program's modes, in one policy object the path loop asks: which light a path keeps
// (accumulate-bounces), how direct light is found (-H hemisphere probes, each delta light once) and
// whether an emitter no light samples lights anything (--emitters camera). With the defaults it
// keeps every bounce and finds direct light by light sampling (docs/cs184.md).
#pragma once

#include <cstddef>

#include "integrators/path_options.h"

namespace kiln {

struct Cs184Rules {
    int maxDepth = 5;
    bool accumulateBounces = true;  // false: only light that bounced exactly maxDepth times
    bool hemisphere = false;        // -H: uniform hemisphere probes find direct light
    // Only (a few) delta lights: next-event estimation takes each light once per vertex (CS184's
    // "a point light gets one sample": more samples of a point would repeat the same ray).
    bool eachDeltaLightOnce = false;
    bool unsampledEmittersLight = true;  // false: such emitters light camera rays and probes only

    // Up to 64 delta lights, as the course does; beyond that (a many-light scene) a shadow ray per
    // light per vertex would swamp the render, and -l picks by power instead.
    static constexpr size_t kMaxDeltaLightsTakenEach = 64;

    Cs184Rules() = default;
    Cs184Rules(const PathOptions& o, size_t lights, bool allDelta)
        : maxDepth(o.maxDepth),
          accumulateBounces(o.accumulateBounces),
          hemisphere(o.sampling == DirectSampling::Hemisphere),
          eachDeltaLightOnce(lights > 0 && lights <= kMaxDeltaLightsTakenEach && allDelta),
          unsampledEmittersLight(o.unsampledEmittersLight) {}

    // Light that bounced `bounce` times counts in the image.
    bool keeps(int bounce) const { return accumulateBounces || bounce == maxDepth; }
    // Direct light gathered at vertex `bounce` (it will have bounced once more) counts.
    bool gathersAt(int bounce) const { return keeps(bounce + 1); }
    // An emitter found after `bounce` bounces that no light samples (li < 0) lights the path.
    bool emitterLights(int li, int bounce) const {
        return li >= 0 || bounce == 0 || unsampledEmittersLight;
    }
    // Shadow rays per vertex and the weight each estimate carries (1 / the number averaged).
    int lightSamplesPerVertex(int lightSamples, size_t lights) const {
        return eachDeltaLightOnce ? int(lights) : lightSamples;
    }
};

}  // namespace kiln
