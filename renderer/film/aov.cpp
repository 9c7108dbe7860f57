#include "renderer/film/aov.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace kiln {
namespace {

struct NamedAov {
    const char* name;
    AovKind kind;
};
constexpr NamedAov kNames[] = {
    {"emission", AovKind::Emission},
    {"direct", AovKind::Direct},
    {"indirect", AovKind::Indirect},
    {"direct_diffuse", AovKind::DirectDiffuse},
    {"direct_specular", AovKind::DirectSpecular},
    {"direct_transmission", AovKind::DirectTransmission},
    {"indirect_diffuse", AovKind::IndirectDiffuse},
    {"indirect_specular", AovKind::IndirectSpecular},
    {"indirect_transmission", AovKind::IndirectTransmission},
    {"direct_subsurface", AovKind::DirectSubsurface},
    {"indirect_subsurface", AovKind::IndirectSubsurface},
    {"direct_volume", AovKind::DirectVolume},
    {"indirect_volume", AovKind::IndirectVolume},
    {"bounces", AovKind::Bounces},
    {"albedo", AovKind::Albedo},
    {"N", AovKind::Normal},
    {"P", AovKind::Position},
    {"Z", AovKind::Depth},
    {"samples", AovKind::Samples},
    {"variance", AovKind::Variance},
    {"primid", AovKind::PrimId},
    {"objectid", AovKind::ObjectId},
    {"crypto_object", AovKind::CryptoObject},
    {"crypto_material", AovKind::CryptoMaterial},
};

// Flattened field numbering used by gather(): colours take 3 consecutive fields.
enum Field {
    kEmission = 0,
    kDirect = 3,
    kIndirect = 6,
    kLobes = 9,                                   // 2 x kLobeCount lobes x 3 = 30 fields
    kBounces = kLobes + 2 * int(kLobeCount) * 3,  // kMaxBounceLayers x 3
    kAlbedo = kBounces + 3 * kMaxBounceLayers,
    kNormal = kAlbedo + 3,
    kPosition = kNormal + 3,
    kPrimId = kPosition + 3,
    kObjectId = kPrimId + 1
};

// The per-lobe layers: [0 direct / 1 indirect][Lobe], with their names' lobe part.
constexpr AovKind kLobeKinds[2][kLobeCount] = {
    {AovKind::DirectDiffuse, AovKind::DirectSpecular, AovKind::DirectTransmission,
     AovKind::DirectSubsurface, AovKind::DirectVolume},
    {AovKind::IndirectDiffuse, AovKind::IndirectSpecular, AovKind::IndirectTransmission,
     AovKind::IndirectSubsurface, AovKind::IndirectVolume}};
constexpr const char* kLobeNames[kLobeCount] = {"diffuse", "specular", "transmission", "subsurface",
                                                "volume"};

int lobeField(size_t d, size_t l) { return kLobes + 3 * int(kLobeCount * d + l); }

constexpr uint32_t bit(AovKind k) { return 1u << uint32_t(k); }

// The light-path AOVs' bits: the integrator splits the beauty's light into them.
constexpr uint32_t kLightBits = [] {
    uint32_t bits = bit(AovKind::Emission) | bit(AovKind::Direct) | bit(AovKind::Indirect) |
                    bit(AovKind::Bounces);
    for (const auto& kinds : kLobeKinds)
        for (AovKind k : kinds) bits |= bit(k);
    return bits;
}();

bool isLight(AovKind k) { return kLightBits & bit(k); }

// The names of the light-path kinds in bits, in kNames' order, joined by separator.
std::string lightNamesIn(uint32_t bits, const char* separator) {
    std::string names;
    for (const NamedAov& n : kNames)
        if (isLight(n.kind) && (bits & bit(n.kind))) {
            if (!names.empty()) names += separator;
            names += n.name;
        }
    return names;
}

}  // namespace

bool AovRequest::splitsLight() const { return mask & kLightBits; }

const char* AovRequest::lightNames() {
    static const std::string names = lightNamesIn(kLightBits, ", ");
    return names.c_str();
}

uint32_t AovRequest::parseDenoised(const std::string& list) {
    uint32_t bits = 0;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        const NamedAov* named = nullptr;
        for (const NamedAov& n : kNames)
            if (item == n.name) named = &n;
        if (!named)
            throw std::invalid_argument("unknown AOV '" + item +
                                        "' (light-path AOVs: " + lightNames() + ")");
        if (!isLight(named->kind))
            throw std::invalid_argument(
                "'" + item + "' is not a light-path AOV (light-path AOVs: " + lightNames() + ")");
        bits |= bit(named->kind);
    }
    if (!bits) throw std::invalid_argument("names no AOV");
    return bits;
}

std::string AovRequest::namesOf(uint32_t bits) { return lightNamesIn(bits, ","); }

std::string AovRequest::allNamesOf(uint32_t mask) {
    std::vector<std::string> names;
    for (const NamedAov& n : kNames)
        if (mask & bit(n.kind)) names.push_back(n.name), mask &= ~bit(n.kind);
    if (mask) names.push_back(std::to_string(mask));  // kinds without a name
    return names.empty() ? "none" : fmt::format("{}", fmt::join(names, ","));
}

AovRequest AovRequest::defaults() {
    AovRequest r;
    for (AovKind k : {AovKind::Emission, AovKind::Direct, AovKind::Indirect, AovKind::Albedo,
                      AovKind::Normal, AovKind::Depth, AovKind::Samples, AovKind::Variance})
        r.add(k);
    return r;
}

const char* AovRequest::names() {
    return "emission, direct, indirect, direct_diffuse, direct_specular, direct_transmission, "
           "direct_subsurface, direct_volume, indirect_diffuse, indirect_specular, "
           "indirect_transmission, indirect_subsurface, indirect_volume, bounces, albedo, N, P, Z, "
           "samples, variance, primid, objectid, crypto_object, crypto_material; or all, none, "
           "default";
}

AovRequest AovRequest::parse(const std::string& list, int maxDepth) {
    AovRequest r;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        if (item == "none") continue;
        if (item == "default") {
            r.mask |= defaults().mask;
            continue;
        }
        if (item == "all") {
            for (const NamedAov& n : kNames) r.add(n.kind);
            continue;
        }
        bool found = false;
        for (const NamedAov& n : kNames)
            if (item == n.name) r.add(n.kind), found = true;
        if (!found)
            throw std::invalid_argument("unknown AOV '" + item + "' (known: " + names() + ")");
    }
    if (r.has(AovKind::Bounces)) r.bounceLayers = std::clamp(maxDepth, 1, kMaxBounceLayers);
    return r;
}

AovLayout::AovLayout(const AovRequest& request) : request_(request) {
    auto colour = [&](const std::string& layer, int field, const char* suffix = "RGB",
                      bool radiance = false) {
        for (int c = 0; c < 3; ++c)
            channels_.push_back({layer + "." + std::string(1, suffix[c]), suffix[0] == 'R', false,
                                 field + c, radiance});
    };
    auto light = [&](const std::string& layer, int field, AovKind kind) {
        if (request.denoises(kind)) denoised_.push_back({layer, channels_.size()});
        colour(layer, field, "RGB", true);
    };
    if (request.has(AovKind::Emission)) light("emission", kEmission, AovKind::Emission);
    if (request.has(AovKind::Direct)) light("direct", kDirect, AovKind::Direct);
    if (request.has(AovKind::Indirect)) light("indirect", kIndirect, AovKind::Indirect);
    for (size_t d = 0; d < 2; ++d)
        for (size_t l = 0; l < kLobeCount; ++l)
            if (request.has(kLobeKinds[d][l]))
                light(std::string(d == 0 ? "direct_" : "indirect_") + kLobeNames[l],
                      lobeField(d, l), kLobeKinds[d][l]);
    for (int b = 0; b < request.bounceLayers; ++b)
        light("bounce" + std::to_string(b + 1), kBounces + 3 * b, AovKind::Bounces);
    if (request.has(AovKind::Albedo)) colour("albedo", kAlbedo);
    if (request.has(AovKind::Normal)) colour("N", kNormal, "XYZ");
    if (request.has(AovKind::Position)) colour("P", kPosition, "XYZ");
    // Z, samples, variance and Cryptomatte have accumulators of their own in the film.
    if (request.has(AovKind::PrimId)) channels_.push_back({"primid.X", false, true, kPrimId});
    if (request.has(AovKind::ObjectId)) channels_.push_back({"objectid.X", false, true, kObjectId});
}

void AovLayout::gather(const SampleRecord& r, double* out) const {
    // Flatten every field once; channels pick theirs. Cheap next to a path.
    double f[kObjectId + 1];
    auto put = [&](int at, const Vec3& v) { f[at] = v.x, f[at + 1] = v.y, f[at + 2] = v.z; };
    put(kEmission, r.emission);
    put(kDirect, r.direct);
    put(kIndirect, r.indirect);
    for (size_t d = 0; d < 2; ++d)
        for (size_t l = 0; l < kLobeCount; ++l) put(lobeField(d, l), r.lobes[d][l]);
    for (int b = 0; b < request_.bounceLayers; ++b) put(kBounces + 3 * b, r.bounces[b]);
    put(kAlbedo, r.albedo);
    put(kNormal, r.normal);
    put(kPosition, r.position);
    f[kPrimId] = r.primId, f[kObjectId] = r.objectId;
    for (size_t c = 0; c < channels_.size(); ++c) out[c] = f[channels_[c].field];
}

}  // namespace kiln
