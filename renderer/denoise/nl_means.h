// Non-local means weights (Buades et al. 2005) with the variance-cancelled patch distance of
// Rousselle et al. 2012, "Adaptive rendering with non-local means filtering", as NFOR uses them
// (Bitterli et al. 2016, section 5): the weight of neighbour q for pixel p compares the patches
// around p and q of a guide image, each squared difference less what the guide's own noise
// explains, over the noise.
#pragma once

#include <vector>

#include "renderer/denoise/image.h"

namespace kiln::denoise {

struct NlMeansParams {
    int patchRadius = 3;      // F: patches of (2F+1)^2 pixels
    int windowRadius = 5;     // R: neighbours within (2R+1)^2
    float k = 0.5f;           // bandwidth: larger averages more
    float varianceScale = 1;  // the guide's variance is variance * varianceScale (2: a half)
    // The image is the guide wherever the variance is 0 (features: both halves agree there): a
    // tile whose whole reach is noise-free is kept as it is, unfiltered.
    bool keepNoiseFree = false;
};

// The weights of every neighbour offset for the pixels of one tile: weight(o, x, y) for offset o
// (row-major over [-R, R]^2) and tile pixel (x, y); 0 where the neighbour lies outside the image.
// The patch distances are kept, so weights at another bandwidth cost only an exp each.
class TileWeights {
  public:
    // The patch distances; guide and variance have the same channels (variance: of each guide
    // value). params.k is not used: weigh() applies a bandwidth.
    void compute(const Image& guide, const Image& variance, const Rect& tile,
                 const NlMeansParams& params);
    // The weights at bandwidth k.
    void weigh(float k);
    int offsets() const { return (2 * radius_ + 1) * (2 * radius_ + 1); }
    const float* offset(int o) const { return &weights_[size_t(o) * plane_]; }

  private:
    void copyRegion(const Image& guide, const Image& variance, const Rect& tile, int margin,
                    float varianceScale);
    void patchSums(int tw, int th, int pw, int ph, int F);
    Rect tile_;
    int radius_ = 0, regionWidth_ = 0, imageWidth_ = 0, imageHeight_ = 0;
    size_t pixels_ = 0, plane_ = 0;      // a tile's pixels; the planes' spacing
    std::vector<float> patchDistances_;  // the patch mean distance per offset and pixel, >= 0
    std::vector<float> weights_, distance_, rows_, patch_;
    std::vector<double> columns_;  // patchSums' running sums along columns
    std::vector<float> region_;    // copyRegion: guide planes, then variance planes
};

// The NL-means filter of image (any channels) with weights from guide and variance; one weight
// per neighbour for all channels. TBB-parallel over tiles, each pixel written by one tile:
// bit-identical for any thread count.
Image nlMeans(const Image& image, const Image& guide, const Image& variance,
              const NlMeansParams& params);

}  // namespace kiln::denoise
