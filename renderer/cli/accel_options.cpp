#include "renderer/cli/accel_options.h"

namespace kiln {

void AcceleratorChoice::addOptions(ArgParser& parser, bool withKind) {
    if (withKind)
        parser.option(
            "accel", "", 1, "embree|reference", "traversal: Embree (default) or the reference BVH",
            [this](const std::vector<std::string>& v) {
                if (v[0] == "embree")
                    kind = AcceleratorKind::Embree;
                else if (v[0] == "reference")
                    kind = AcceleratorKind::Reference;
                else
                    throw UsageError("--accel takes 'embree' or 'reference', got '" + v[0] + "'");
            });
    parser.option(
        "embree-quality", "", 1, "low|medium|high", "Embree BVH build quality (default medium)",
        [this](const std::vector<std::string>& v) {
            if (v[0] == "low")
                embree.quality = EmbreeOptions::Quality::Low;
            else if (v[0] == "medium")
                embree.quality = EmbreeOptions::Quality::Medium;
            else if (v[0] == "high")
                embree.quality = EmbreeOptions::Quality::High;
            else
                throw UsageError("--embree-quality takes low, medium or high, got '" + v[0] + "'");
        });
    parser.option("no-robust", "", 0, "",
                  "drop RTC_SCENE_FLAG_ROBUST (faster, may leak through shared edges)",
                  [this](const std::vector<std::string>&) { embree.robust = false; });
    parser.option("watertight", "", 0, "",
                  "Embree traverses, kiln's double-precision test intersects triangles: no leaks "
                  "at shared vertices either (slower)",
                  [this](const std::vector<std::string>&) { embree.watertight = true; });
    parser.option("compact", "", 0, "", "RTC_SCENE_FLAG_COMPACT: smaller Embree BVH",
                  [this](const std::vector<std::string>&) { embree.compact = true; });
    parser.option(
        "bvh-split", "", 1, "sah|mean|midpoint", "reference BVH split rule (default sah)",
        [this](const std::vector<std::string>& v) {
            if (v[0] == "sah")
                reference.split = BvhSplit::Sah;
            else if (v[0] == "mean")
                reference.split = BvhSplit::MeanCentroid;
            else if (v[0] == "midpoint")
                reference.split = BvhSplit::Midpoint;
            else
                throw UsageError("--bvh-split takes sah, mean or midpoint, got '" + v[0] + "'");
        });
    parser.intOption("bvh-leaf", "", "reference BVH maximum leaf size (default 4)",
                     reference.maxLeafSize, 1, 255);
}

std::unique_ptr<Accelerator> AcceleratorChoice::build(const Scene& scene) const {
    if (kind == AcceleratorKind::Reference) return makeReferenceAccelerator(scene, reference);
    return makeEmbreeAccelerator(scene, embree);
}

}  // namespace kiln
