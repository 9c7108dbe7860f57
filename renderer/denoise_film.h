// The denoiser (renderer/denoise, docs/denoise.md) applied to what kiln renders: a film kept with
// half-buffers (kiln render --denoise), or an EXR that carries them (kiln denoise).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "color/exr_image.h"
#include "color/image_output.h"
#include "renderer/denoise/denoiser.h"
#include "renderer/film/film.h"

namespace kiln {

// The film's half-buffers as the denoiser takes them (a film with AovKind::DenoiseHalves): the
// beauty's colour, or with layer >= 0 the colour of the denoised light-path layer
// layout().denoisedLayers()[layer] (its own variance), with the same features.
denoise::Halves halvesOf(const Film& film, int layer = -1);

// The film's beauty (or denoised layer, as halvesOf) denoised (premultiplied, as the film's),
// row-major.
std::shared_ptr<const std::vector<Color>> denoiseFilm(const Film& film,
                                                      const denoise::Options& options,
                                                      int layer = -1);

// The film's denoised beauty into exr (ExrOptions::denoised: the EXR's R,G,B and the preview),
// its denoised light-path layers (--denoise-aovs) into ExrOptions::denoisedLayers, and what the
// header says of them into meta (kiln:denoised, kiln:denoised_aovs, kiln:denoise_seconds).
void denoiseForOutputs(const Film& film, int threads, ExrOptions& exr, Metadata& meta);

// What is wrong with an EXR given to kiln denoise; what() is one line naming the file.
struct DenoiseInputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The half-buffers of an EXR written by kiln render --denoise (or kiln merge of such shards); with
// a layer ("direct"), that light-path layer's colour halves (halfA.direct.*, --denoise-aovs) in
// place of the beauty's. Throws DenoiseInputError: no or incomplete half-buffers, half sample
// counts that do not add up to samples.count, non-finite values.
denoise::Halves halvesOf(const ExrImage& exr, const std::string& path,
                         const std::string& layer = "");

// kiln denoise IN -o OUT: OUT is IN with R,G,B denoised, the noisy beauty as noisy.R/G/B (kept
// from IN when IN was denoised before) and kiln:denoised naming the method; likewise each layer
// of the light-path kinds in denoisedLight (AovRequest bits; bounces: every bounceN layer IN
// has), as LAYER.R/G/B and noisy.LAYER.R/G/B, named in kiln:denoised_aovs. Every input is checked
// before any denoising. Returns the seconds the denoiser took. Throws DenoiseInputError,
// ImageReadError, std::runtime_error (the write).
double denoiseExr(const std::string& in, const std::string& out, const denoise::Options& options,
                  uint32_t denoisedLight = 0);

}  // namespace kiln
