#include <fmt/format.h>

#include <cstdio>

#include "renderer/cli/accel_options.h"
#include "renderer/cli/commands.h"
#include "renderer/core/log.h"
#include "renderer/validation/crosscheck.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

const char* kindName(Disagreement d) {
    switch (d) {
        case Disagreement::None:
            return "agree";
        case Disagreement::Edge:
            return "edge";
        case Disagreement::Coplanar:
            return "coplanar";
        case Disagreement::Genuine:
            return "GENUINE";
    }
    return "?";
}

void printHit(const char* label, const Hit& h) {
    if (!h.valid()) {
        std::printf("  %s: miss\n", label);
        return;
    }
    std::printf("  %s: t %.9g shape %d prim %u instance %d u %.9g v %.9g\n", label, h.t,
                h.shape == kSphereShape ? -2 : int(h.shape), h.prim,
                h.instance == kInvalidId ? -1 : int(h.instance), h.u, h.v);
}

}  // namespace

int runCrosscheck(const std::vector<std::string>& args) {
    ArgParser parser("crosscheck", "SCENE [--rays N] [--json] [--replay RAY]");
    int rays = 1000000, maxGenuine = 0, seed = 1;
    bool json = false;
    std::string replay;
    AcceleratorChoice choice;
    parser.intOption(
        "rays", "",
        "total rays, split evenly over camera/random/secondary/shadow (default 1000000)", rays, 4,
        1 << 30);
    parser.intOption("max-genuine", "", "genuine mismatches tolerated before exit 1 (default 0)",
                     maxGenuine, 0, 1 << 30);
    parser.intOption("seed", "", "ray seed (default 1)", seed, 0, 1 << 30);
    parser.flag("json", "", "machine-readable report", json);
    parser.option("replay", "", 1, "RAY",
                  "trace one ray given as printed in a report (8 hex floats, quoted)",
                  [&](const std::vector<std::string>& v) { replay = v[0]; });
    choice.addOptions(parser, false);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1)
        throw UsageError("needs exactly one scene file (see 'kiln crosscheck --help')");
    // Checked before the load and the builds; the origin against the span kiln traces after it.
    Ray ray;
    if (!replay.empty() && !parseRay(replay, ray))
        throw UsageError(
            "--replay needs 8 numbers: ox oy oz dx dy dz tmin tmax, finite (tmax may "
            "be inf), a direction that is not zero and 0 <= tmin <= tmax; got '" +
            replay + "'");
    Scene scene = loadScene(pos[0]);
    if (!replay.empty()) {
        Bounds3 withRay = scene.storedBounds();
        withRay.extend(ray.origin);
        if (!(maxComponent(withRay.diagonal()) <= kMaxSceneExtent &&
              maxComponent(abs(ray.origin)) <= kMaxSceneExtent))
            throw UsageError(
                fmt::format("--replay: the ray's origin is beyond the span kiln "
                            "traces ({:.0e} units)",
                            double(kMaxSceneExtent)));
    }
    auto embree = makeEmbreeAccelerator(scene, choice.embree);
    auto reference = makeReferenceAccelerator(scene, choice.reference);

    if (!replay.empty()) {
        RayComparison c = compareRay(scene, *embree, *reference, ray, true);
        std::printf("ray %s\n", formatRay(ray).c_str());
        printHit("embree   ", c.a);
        printHit("reference", c.b);
        std::printf("  occluded: embree %d reference %d\n  verdict: %s %s\n", c.occludedA,
                    c.occludedB, kindName(c.kind), c.reason.c_str());
        return c.kind == Disagreement::Genuine ? 1 : 0;
    }

    CrosscheckReport report =
        crosscheck(scene, *embree, *reference, size_t(rays) / 4, uint64_t(seed));
    if (json) {
        std::puts(jsonText(crosscheckJson(report, pos[0])).c_str());
    } else {
        std::printf("crosscheck %s: embree (%s) vs reference (%s)\n", pos[0].c_str(),
                    embree->stats().description.c_str(), reference->stats().description.c_str());
        std::printf("%-10s %10s %10s %10s %10s %8s %9s %8s %11s %10s\n", "rays", "count", "hit emb",
                    "hit ref", "agree", "edge", "coplanar", "genuine", "max |dt|/t", "max dbary");
        for (const CrosscheckCategory& c : report.categories)
            std::printf("%-10s %10llu %10llu %10llu %10llu %8llu %9llu %8llu %11.3g %10.3g\n",
                        toString(c.kind), (unsigned long long)c.rays, (unsigned long long)c.hitsA,
                        (unsigned long long)c.hitsB, (unsigned long long)c.agree,
                        (unsigned long long)c.edge, (unsigned long long)c.coplanar,
                        (unsigned long long)c.genuine, c.maxRelativeDt, c.maxBaryDiff);
        for (const CrosscheckCategory& c : report.categories)
            for (const RayComparison& w : c.worst) {
                std::printf("\n%s ray, %s%s%s, |dt|/t %.3g: replay with --replay \"%s\"\n",
                            toString(c.kind), kindName(w.kind), w.reason.empty() ? "" : ": ",
                            w.reason.c_str(), w.relativeDt, formatRay(w.ray).c_str());
                printHit("embree   ", w.a);
                printHit("reference", w.b);
            }
    }
    if (report.totalGenuine() > uint64_t(maxGenuine)) {
        logMessage(
            LogLevel::Error,
            fmt::format("{} genuine mismatches (bound {})", report.totalGenuine(), maxGenuine),
            "crosscheck");
        return 1;
    }
    return 0;
}

}  // namespace kiln
