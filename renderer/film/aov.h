// Arbitrary output variables: what the user may request, what one camera sample records, and how
// the film lays the requested ones out as EXR channels ("layer.channel").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/core/enum_names.h"
#include "renderer/core/math.h"

namespace kiln {

enum class AovKind : uint32_t {
    Emission,  // light seen directly (zero bounce)
    Direct,    // light after one bounce
    Indirect,  // light after two or more bounces
    DirectDiffuse,
    DirectSpecular,
    DirectTransmission,  // direct, split by the first vertex's lobe
    IndirectDiffuse,
    IndirectSpecular,
    IndirectTransmission,  // indirect, likewise
    Bounces,               // bounce1, bounce2, ...: light after exactly k bounces
    Albedo,
    Normal,
    Position,
    Depth,  // first visible surface
    Samples,
    Variance,  // per pixel: sample count, estimator variance of the luminance mean
    PrimId,
    ObjectId,
    CryptoObject,
    CryptoMaterial,  // Cryptomatte layers (ranked id/coverage pairs), see film/cryptomatte.h
    // The lobe split, continued (after the others so that checkpoints' masks keep their bits):
    // light that left its first vertex through a subsurface walk, or scattered first in a medium.
    DirectSubsurface,
    DirectVolume,
    IndirectSubsurface,
    IndirectVolume,
    Count,
    // Not a layer users list (--aov, "all"): the film's even/odd half-buffers of colour and
    // features for the denoiser (half_buffers.h), set by --denoise. A mask bit, so checkpoints,
    // fingerprints and merges carry it with the AOVs.
    DenoiseHalves = 31
};

// What Z holds: the distance along the camera ray, or camera-space z (the distance along the view
// axis, as OpenEXR's worldToCamera space and Nuke's/Blender's depth passes have it).
enum class DepthMode { Ray, CameraZ };
template <>
struct EnumNames<DepthMode> {
    static constexpr std::pair<DepthMode, const char*> table[] = {{DepthMode::Ray, "ray"},
                                                                  {DepthMode::CameraZ, "camera"}};
};

constexpr int kMaxBounceLayers = 16;

struct AovRequest {
    uint32_t mask = 0;
    int bounceLayers = 0;  // with Bounces: bounce1..bounceN
    // Cycles' Film > Transparent: light seen straight through to the background leaves the image,
    // and emitters seen directly do not cover (alpha counts only non-emitting surfaces).
    bool transparent = false;
    DepthMode depth = DepthMode::Ray;
    // --denoise-aovs: the light-path kinds (bits as in mask) whose layers the film keeps
    // half-buffers of and the denoiser filters (with DenoiseHalves; docs/denoise.md).
    uint32_t denoisedLight = 0;
    bool has(AovKind k) const { return mask & (1u << uint32_t(k)); }
    bool denoises(AovKind k) const { return denoisedLight & (1u << uint32_t(k)); }
    void add(AovKind k) { mask |= 1u << uint32_t(k); }
    // Any of the light-path AOVs (the integrator must classify its contributions).
    bool splitsLight() const;
    // The integrator records the albedo (the AOV or the denoiser's feature).
    bool recordsAlbedo() const { return has(AovKind::Albedo) || has(AovKind::DenoiseHalves); }
    // "emission,direct,..." or "all", "none", "default". Throws std::invalid_argument naming the
    // bad entry.
    static AovRequest parse(const std::string& list, int maxDepth);
    static AovRequest defaults();  // beauty plus what compositing and denoising usually want
    static const char* names();    // for --help
    // --denoise-aovs "direct,indirect": the light-path kinds named (bits as in mask; "bounces":
    // every bounceN layer). Throws std::invalid_argument naming an unknown or non-light entry.
    static uint32_t parseDenoised(const std::string& list);
    static const char* lightNames();  // the light-path AOVs, for --help
    // The names of the light-path kinds in bits (as --aov spells them), comma-separated.
    static std::string namesOf(uint32_t bits);
    // Every AOV's name in a mask, joined by commas ("none" for none): the fingerprint's words.
    static std::string allNamesOf(uint32_t mask);
};

// How light left the path's first vertex, as Cycles' Diffuse, Glossy, Transmission, Subsurface
// and Volume passes split it.
enum class Lobe { Diffuse = 0, Specular = 1, Transmission = 2, Subsurface = 3, Volume = 4 };
constexpr size_t kLobeCount = 5;

// N colours that construction leaves unset (a Color zeroes itself): SampleRecord's per-lobe and
// per-bounce sums, which reset() zeroes only when a render asks for them.
template <size_t N>
struct UnsetColours {
    UnsetColours() {}  // NOLINT: deliberately no initialisation
    Color& operator[](size_t i) { return v[i]; }
    const Color& operator[](size_t i) const { return v[i]; }
    union {
        Color v[N];
    };
};

// What one camera sample produced. Only the requested parts are filled; the per-lobe and per-bounce
// arrays are zeroed by reset() only when requested (zeroing them for every sample cost about 10 %;
// they were still zeroed on construction, by Color's own initialisers, until UnsetColours).
struct SampleRecord {
    Color L{0.0f};
    Color emission{0.0f}, direct{0.0f}, indirect{0.0f};
    Color albedo{0.0f};
    Vec3 normal{0.0f}, position{0.0f};
    bool hit = false;                              // the camera ray hit a surface (alpha coverage)
    bool hitEmitter = false;                       // ... and that surface emits light
    float depth = kInfinity, cameraZ = kInfinity;  // first hit: along the ray, along the view axis
    float primId = -1, objectId = -1;
    uint32_t cryptoObject = 0, cryptoMaterial = 0;  // Cryptomatte id float bits; 0: none
    // Last: what every sample writes stays in as few cache lines as it can (a render's batch of
    // records streams through the cache), these only where AOVs split the light.
    UnsetColours<kLobeCount> lobes[2];  // [0 direct / 1 indirect][Lobe]
    UnsetColours<kMaxBounceLayers> bounces;
    void reset(const AovRequest& aovs) {
        if (!aovs.splitsLight()) return;
        for (auto& d : lobes)
            for (size_t l = 0; l < kLobeCount; ++l) d[l] = Color(0.0f);
        for (int b = 0; b < aovs.bounceLayers; ++b) bounces[size_t(b)] = Color(0.0f);
    }
};

// One EXR channel fed from a SampleRecord field.
struct AovChannel {
    std::string name;          // "direct.R", "N.X", "primid.X", ...
    bool colour = true;        // may be written as half
    bool firstSample = false;  // ids: the first sample's value, never averaged
    int field = 0;             // index into the record's flattened values (see AovLayout::gather)
    bool radiance = false;     // light: held in the film's radiance scale (Film::scaleExponent)
};

// A light-path layer the denoiser filters (AovRequest::denoisedLight): its name and its R channel
// in the layout (G and B follow).
struct DenoisedLayer {
    std::string name;  // "direct", "indirect_diffuse", "bounce2", ...
    size_t channel = 0;
};

class AovLayout {
  public:
    explicit AovLayout(const AovRequest& request);
    const std::vector<AovChannel>& channels() const { return channels_; }
    // The requested layers of the kinds in denoisedLight, in channel order.
    const std::vector<DenoisedLayer>& denoisedLayers() const { return denoised_; }
    const AovRequest& request() const { return request_; }
    // Writes the record's requested values, in channel order.
    void gather(const SampleRecord& r, double* out) const;

  private:
    AovRequest request_;
    std::vector<AovChannel> channels_;
    std::vector<DenoisedLayer> denoised_;
};

}  // namespace kiln
