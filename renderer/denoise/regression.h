// NFOR's collaborative first-order regression (Bitterli et al. 2016, section 5.2): around each
// pixel p, a weighted least-squares fit of colour on [1, screen offset, feature - feature(p)]
// over the window, with NL-means weights from a guide; the fitted plane is evaluated at every
// window pixel and each pixel's result is the weighted mean of all fits that cover it.
#pragma once

#include <vector>

#include "renderer/denoise/image.h"
#include "renderer/denoise/nl_means.h"

namespace kiln::denoise {

struct RegressionParams {
    NlMeansParams weights;          // the window and the NL-means weights' patch and guide
    std::vector<float> bandwidths;  // one result per bandwidth k (the weights' k is unused)
    // Fits only at pixels whose coordinates are multiples of fitStride (Moon et al. 2015's sparse
    // centres): each pixel is still covered by about ((2R+1)/fitStride)^2 fits.
    int fitStride = 1;
};

// colour: 3 channels; guide and variance: 3 channels (the guide's per-channel variance);
// features: any number. The patch distances are found once for all bandwidths. Deterministic:
// the fits are added in a fixed order whatever the threads (tiles of four classes, tiles of one
// class never writing the same pixel).
std::vector<Image> collaborativeRegression(const Image& colour, const Image& guide,
                                           const Image& features, const Image& variance,
                                           const RegressionParams& params);

}  // namespace kiln::denoise
