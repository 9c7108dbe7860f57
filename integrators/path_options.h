// What a path tracer is asked to do: the direct-light strategy, roulette, bounce rules and guiding,
// as the command line, the render job and the checkpoint fingerprint name them.
#pragma once

#include "integrators/microfacet.h"
#include "renderer/core/enum_names.h"

namespace kiln {

// Direct light at a vertex: uniform hemisphere probes (CS184's -H), light sampling only, MIS of
// light and BSDF sampling (power or balance heuristic), or BSDF sampling only (no shadow rays:
// light is found where the continuing path hits it; blind to point, spot and directional lights).
enum class DirectSampling { Hemisphere, Light, Mis, Bsdf };
enum class Roulette { Off, Throughput, Fixed };
enum class IntegratorKind { Path, Normals };
enum class MisHeuristic { Power, Balance };
// Path guiding of diffuse bounces (guiding.h): auto leaves it to the render plan.
enum class GuideMode { Auto, On, Off };

template <>
struct EnumNames<DirectSampling> {
    static constexpr std::pair<DirectSampling, const char*> table[] = {
        {DirectSampling::Mis, "mis"},
        {DirectSampling::Light, "light"},
        {DirectSampling::Hemisphere, "hemisphere"},
        {DirectSampling::Bsdf, "bsdf"}};
};
template <>
struct EnumNames<Roulette> {
    static constexpr std::pair<Roulette, const char*> table[] = {
        {Roulette::Throughput, "throughput"}, {Roulette::Fixed, "fixed"}, {Roulette::Off, "off"}};
};
template <>
struct EnumNames<IntegratorKind> {
    static constexpr std::pair<IntegratorKind, const char*> table[] = {
        {IntegratorKind::Path, "path"}, {IntegratorKind::Normals, "normals"}};
};
template <>
struct EnumNames<GuideMode> {
    static constexpr std::pair<GuideMode, const char*> table[] = {
        {GuideMode::Auto, "auto"}, {GuideMode::On, "on"}, {GuideMode::Off, "off"}};
};
template <>
struct EnumNames<MisHeuristic> {
    static constexpr std::pair<MisHeuristic, const char*> table[] = {
        {MisHeuristic::Power, "power"}, {MisHeuristic::Balance, "balance"}};
};

struct PathOptions {
    int maxDepth = 5;
    int lightSamples = 0;  // -l: light samples per shading point; 0: the plan's default
    DirectSampling sampling = DirectSampling::Mis;
    MisHeuristic heuristic = MisHeuristic::Power;
    Roulette roulette = Roulette::Throughput;
    float fixedContinuation = 0.65f;  // CS184's constant continuation probability (Roulette::Fixed)
    // Throughput roulette starts once a path has bounced this many times: 5 measured best on the
    // peer benchmark's closed box at -m 5 (earlier roulette added more variance than it saved time:
    // docs/performance.md) and equal on the open and glossy scenes.
    int rouletteMinBounces = 5;
    bool accumulateBounces = true;  // false: only light that bounced exactly maxDepth times
    // false (--emitters camera, the CS184 program): an emitter no light samples is seen by camera
    // rays and -H probes only, and lights nothing after a bounce.
    bool unsampledEmittersLight = true;
    MicrofacetModel microfacet = MicrofacetModel::Beckmann;
    GuideMode guiding = GuideMode::Auto;
    float pixelSpread = 0;  // radians a camera pixel spans: the texture footprint (0: finest level)
};

}  // namespace kiln
