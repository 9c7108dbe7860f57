#include "renderer/cli/cs184_prose.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace kiln::cs184 {

std::string fixed(double v, int digits) { return fmt::format("{:.{}f}", v, digits); }

std::string taskIntro(int part, int task) {
    static const std::map<std::pair<int, int>, std::string> text = {
        {{1, 1},
         "A camera ray starts at the pinhole and passes through a point of the sensor. The "
         "course places the sensor at z = -1 in camera space and spans it by tan(hFov/2) and "
         "tan(vFov/2): the image point (x, y) in [0,1]^2 maps to the direction "
         "d = ((2x - 1) tan(hFov/2), (2y - 1) tan(vFov/2), -1), turned into world space by the "
         "camera-to-world rotation and normalised; the ray is o + t d for t between the near and "
         "far clip. kiln's pinhole does the same, with the field of view widened in one dimension "
         "to match the image's aspect and kept independent of the resolution (the course fixes "
         "its sensor for an 800x600 window)."},
        {{1, 2},
         "Each pixel (i, j) is estimated from N camera rays (-s N) through points (i + u, j + v) "
         "of the pixel, and the pixel's value is their mean, a Monte Carlo estimate of the "
         "integral of radiance over the pixel's area with pdf 1 (uniform). The course draws u, v "
         "independently; kiln draws them from Owen-scrambled Sobol points, stratified over each "
         "pixel's samples, which makes the same N samples less noisy."},
        {{1, 3},
         "Moller-Trumbore solves o + t d = (1 - b1 - b2) p0 + b1 p1 + b2 p2 for (t, b1, b2) by "
         "Cramer's rule: with e1 = p1 - p0, e2 = p2 - p0, s = o - p0, s1 = d x e2, s2 = s x e1, "
         "(t, b1, b2) = (s2.e2, s1.s, s2.d) / (s1.e1). The ray hits when the barycentrics b1, b2, "
         "1 - b1 - b2 are all in [0, 1] and t lies in [t_min, t_max]; t_max then shrinks to t so "
         "that later tests find only nearer hits. The normal is interpolated with the "
         "barycentrics. kiln's reference BVH uses this test in double precision; Embree uses its "
         "own watertight float test."},
        {{1, 4},
         "A sphere |p - c|^2 = R^2 and the ray o + t d give a quadratic a t^2 + b t + c = 0 with "
         "a = d.d, b = 2 (o - c).d, c = |o - c|^2 - R^2; the discriminant b^2 - 4ac < 0 means a "
         "miss, else the nearer root in [t_min, t_max] (the farther when the nearer is behind) is "
         "the hit and the normal is (p - c) / R. The figure below shades every first hit by its "
         "normal, (n + 1) / 2 as RGB: it checks rays and intersections before any light."},
        {{2, 1},
         "The course builds its BVH top down: a node's bounding box encloses its primitives; "
         "with more than max_leaf_size (4) primitives, it splits them on the longest axis of "
         "their centroids' box at the mean centroid and recurses, so that a ray can skip every "
         "primitive of a box it misses. kiln's reference BVH implements exactly this rule "
         "(--accel reference --bvh-split mean); kiln renders with Embree by default, whose "
         "builder uses the surface area heuristic and wide nodes."},
        {{2, 2},
         "A box is the intersection of three slabs. For the axis x the ray enters and leaves the "
         "slab at t = (x_min - o_x) / d_x and (x_max - o_x) / d_x (swapped when d_x < 0); the ray "
         "meets the box where the largest entry is not after the smallest exit and the interval "
         "overlaps [t_min, t_max]."},
        {{2, 3},
         "Traversal tests the root's box; a missed box skips its whole subtree, a leaf tests its "
         "primitives, and an inner node visits both children (the nearer first, so that a hit "
         "shrinks t_max and prunes the farther one). The table times the course's meshes at the "
         "course's 800x600 with normal shading: Embree, the reference BVH with the course's "
         "split, and no BVH at all (--accel brute: every ray against every primitive)."},
        {{3, 1},
         "A diffuse (Lambertian) surface reflects equally in all directions: "
         "f(wi, wo) = albedo / pi, which integrates to the albedo over the cosine-weighted "
         "hemisphere."},
        {{3, 2},
         "Zero-bounce illumination is the light that reaches the camera without bouncing: the "
         "emission L_e of the surface a camera ray hits (max_ray_depth 0, -m 0)."},
        {{3, 3},
         "Direct lighting is the reflection integral L_o(p, wo) = integral over the hemisphere of "
         "f(wi, wo) L_e(wi) cos(theta_i) dwi, counting only light that arrives straight from an "
         "emitter. Uniform hemisphere sampling estimates it with N directions wi_k of pdf "
         "1 / (2 pi): L_o ~ (1/N) sum_k f L_e(wi_k) cos(theta_k) / (1 / (2 pi)); each direction "
         "is a ray that adds the emission it finds (-H -l N). A direction rarely meets a small "
         "light, and never a point light, so the estimate is noisy."},
        {{3, 4},
         "Importance sampling the lights picks points on the light instead: for an area light of "
         "area A a point x' uniform on it, so the pdf in solid angle is "
         "p(wi) = |x' - p|^2 / (A cos(theta')), theta' the angle at the light; each sample costs "
         "one shadow ray, and L_o ~ (1/N) sum_k f L_e cos(theta_k) / p(wi_k) over the unoccluded "
         "samples. A point light is one sample of pdf 1 (a delta). -l N takes N samples per area "
         "light per shading point; kiln's --sampling light is exactly this estimator (kiln's "
         "default mixes it with BSDF sampling, MIS)."},
        {{4, 1},
         "To continue a path the diffuse BSDF samples its next direction cosine-weighted, "
         "pdf(wi) = cos(theta) / pi, so f cos / pdf = albedo: the throughput is multiplied by the "
         "albedo at every diffuse bounce."},
        {{4, 2},
         "Global illumination adds the light of every longer path: at each vertex next-event "
         "estimation gives the direct light, and the path continues in a BSDF-sampled direction "
         "with its throughput multiplied by f cos / pdf, until max_ray_depth (-m) bounces. The "
         "sum over bounces is L = L_e + L_1 + L_2 + ..., where L_k is the light that bounced k "
         "times; -o 0 (the course's isAccumBounces = false) shows L_m alone."},
        {{4, 3},
         "Russian roulette ends paths at random without bias: after the first bounce a path "
         "continues with probability q (the course's 0.6 to 0.7; kiln's --rr fixed uses 0.65) "
         "and its throughput is divided by q, so the expectation is unchanged while the expected "
         "path length is finite even at -m 100. kiln's default (--rr throughput) continues with "
         "the path's throughput instead, after five bounces."},
        {{5, 0},
         "Adaptive sampling stops a pixel once its mean is known well enough. Every BATCH samples "
         "(-a BATCH TOL) the pixel's sample illuminances x_k give s1 = sum x_k, s2 = sum x_k^2, "
         "mu = s1 / n, sigma^2 = (s2 - s1^2 / n) / (n - 1) and the 95 % confidence half-width "
         "I = 1.96 sigma / sqrt(n); the pixel stops when I <= TOL mu, else it continues up to "
         "-s samples. The sample-rate image colours each pixel by the samples it took, blue few, "
         "red many."},
    };
    auto it = text.find({part, task});
    return it == text.end() ? "" : it->second;
}

double TimingRow::frameSeconds() const {
    return shot.stats.seconds * fullFramePixels / (coveredPixels * spp);
}

namespace {

double mrays(const ShotResult& r) { return double(r.stats.rays) / r.stats.seconds * 1e-6; }

// "0.0123" or "n/a" for an image whose pixels have a single sample.
std::string noiseText(const ImageMeasures& m) {
    return m.noise >= 0 ? fmt::format("{:.4f}", m.noise) : "n/a";
}

std::string timing(const ShotResult& r) {
    return fmt::format("{} s, {:.3g} Mrays, {:.3g} Mrays/s", fixed(r.stats.seconds, 2),
                       double(r.stats.rays) * 1e-6, mrays(r));
}

const char* kNoiseDefinition =
    " Noise here is the median over the lit pixels of the standard error of the pixel's mean "
    "(from its own samples) relative to that mean: a typical pixel's relative error, which "
    "falls as 1/sqrt(samples) for a fixed estimator.";

std::string normals(const SceneShots& s) {
    const ShotResult& r = s.shots[0];
    return fmt::format(
        "{}: {} camera rays ({}x{}, {} sample per pixel) took {}: each pixel's colour is the "
        "normal of the nearest hit, so the shapes and their smooth interpolated normals are "
        "right before any light is computed.",
        s.scene, r.stats.rays, r.width, r.height, r.spp, timing(r));
}

std::string zero(const SceneShots& s) {
    const ShotResult& r = s.shots[0];
    return fmt::format(
        "{}: only the emitters are visible; the image's mean luminance is {:.4f} from camera "
        "rays alone ({}).",
        s.scene, r.image.meanLuminance, timing(r));
}

// Hemisphere and importance sampling: the second figure compares with the first's results.
std::string directCompare(const SceneShots& hemisphere, const SceneShots& importance) {
    const ShotResult &h = hemisphere.shots[0], &l = importance.shots[0];
    double ratio = l.image.noise > 0 ? h.image.noise / l.image.noise : 0;
    return fmt::format(
        "{}: with the same {} camera rays per pixel and the same light rays per shading point, "
        "uniform hemisphere sampling has noise {} and mean luminance {:.4f} ({}); light "
        "importance sampling has noise {} and mean luminance {:.4f} ({}). Hemisphere sampling "
        "is {:.1f} times as noisy: its directions find the light only where they happen to hit "
        "it, while every light sample lands on the light and is weighted by its exact pdf. The "
        "two means agree as far as the noise allows: both estimate the same integral.",
        importance.scene, l.spp, noiseText(h.image), h.image.meanLuminance, timing(h),
        noiseText(l.image), l.image.meanLuminance, timing(l), ratio);
}

std::string lightRays(const SceneShots& s) {
    std::string list;
    for (const ShotResult& r : s.shots)
        list += fmt::format("{}{} ({} s)", list.empty() ? "" : ", ", noiseText(r.image),
                            fixed(r.stats.seconds, 2));
    const ImageMeasures &first = s.shots.front().image, &last = s.shots.back().image;
    return fmt::format(
        "{}: one camera ray per pixel, so a pixel's own samples cannot tell its noise; instead "
        "each image is compared with the 16-sample, 8-light-ray image above (the same "
        "estimator, 128 light samples per pixel): the median relative difference for -l 1, 4, "
        "16, 64 is {}. From 1 to 64 light rays it falls {:.1f} times: the soft shadows fill "
        "in as more of the light's area is sampled at every point. It cannot fall to zero: the "
        "single camera ray still samples one point of the pixel, and the comparison image has "
        "noise of its own.",
        s.scene, list, last.noise > 0 ? first.noise / last.noise : 0);
}

std::string gi(const SceneShots& s) {
    const ShotResult &all = s.shots[0], &direct = s.shots[1], &indirect = s.shots[2];
    double total = direct.image.meanLuminance + indirect.image.meanLuminance;
    return fmt::format(
        "{}: {} samples per pixel, 4 light rays, max_ray_depth 5: {}, noise {}. The direct and "
        "indirect images are the two layers of that one render (kiln's direct and indirect "
        "AOVs), so they add up to it: mean luminance {:.4f} direct and {:.4f} indirect, so "
        "light that bounced more than once is {:.0f} % of the image. Direct light alone leaves "
        "black whatever no light sees (in a Cornell box the ceiling around the lamp and the "
        "shadows); indirect light fills it in.",
        s.scene, all.spp, timing(all), noiseText(all.image), direct.image.meanLuminance,
        indirect.image.meanLuminance, total > 0 ? 100 * indirect.image.meanLuminance / total : 0);
}

std::string luminanceList(const SceneShots& s) {
    std::string list;
    for (const ShotResult& r : s.shots)
        list += fmt::format("{}{:.4f}", list.empty() ? "" : ", ", r.image.meanLuminance);
    return list;
}

std::string bounce(const SceneShots& s) {
    const auto& r = s.shots;
    double l1 = r[1].image.meanLuminance;
    return fmt::format(
        "{}: mean luminance of bounce 0 to 5 alone: {}. The second bounce carries {:.0f} % and "
        "the third {:.0f} % of the first bounce's light: each bounce is scaled by the albedos it "
        "meets, so the sum converges. The second and third bounces are what a rasteriser does "
        "not have: light arriving from walls rather than lamps, which brightens the ceiling, "
        "the shadows and the undersides and bleeds the walls' colours onto their neighbours.",
        s.scene, luminanceList(s), l1 > 0 ? 100 * r[2].image.meanLuminance / l1 : 0,
        l1 > 0 ? 100 * r[3].image.meanLuminance / l1 : 0);
}

std::string depth(const SceneShots& s) {
    const auto& r = s.shots;
    return fmt::format(
        "{}: mean luminance with bounces accumulated up to max_ray_depth 0 to 5: {}; each "
        "step adds the bounce shown alone above, so the images brighten by less at every step "
        "({:.1f} % from -m 4 to -m 5). Rays per camera sample grow with the depth: {:.1f} at "
        "-m 1, {:.1f} at -m 5.",
        s.scene, luminanceList(s),
        r[4].image.meanLuminance > 0
            ? 100 * (r[5].image.meanLuminance / r[4].image.meanLuminance - 1)
            : 0,
        double(r[1].stats.rays) / double(r[1].stats.samples),
        double(r[5].stats.rays) / double(r[5].stats.samples));
}

std::string sweep(const SceneShots& s) {
    std::string list;
    for (const ShotResult& r : s.shots)
        list += fmt::format("{}{} spp {} ({} s)", list.empty() ? "" : ", ", r.spp,
                            noiseText(r.image), fixed(r.stats.seconds, 1));
    const ShotResult *a = nullptr, *b = &s.shots.back();
    for (const ShotResult& r : s.shots)
        if (!a && r.image.noise > 0) a = &r;
    double slope = a && a != b && b->image.noise > 0 ? std::log(b->image.noise / a->image.noise) /
                                                           std::log(double(b->spp) / a->spp)
                                                     : 0;
    return fmt::format(
        "{}: noise at {}. Between {} and {} samples per pixel the noise falls as samples^{:.2f} "
        "(a Monte Carlo estimate's error falls as samples^-0.5): four times the samples halve "
        "the noise, so the last images cost the most and change the least.",
        s.scene, list, a ? a->spp : 0, b->spp, slope);
}

std::string roulette(const SceneShots& s) {
    std::string list;
    for (const ShotResult& r : s.shots)
        list += fmt::format("{}{:.2f}", list.empty() ? "" : ", ",
                            double(r.stats.rays) / double(r.stats.samples));
    const auto& r = s.shots;
    const ShotResult &m4 = r[4], &m100 = r.back();
    return fmt::format(
        "{}: rays per camera sample at -m 0, 1, 2, 3, 4, 100 with --rr fixed: {}. At -m 100 a "
        "path is {:.2f} times as costly as at -m 4, not 25 times: with continuation 0.65 a path "
        "survives k bounces with probability 0.65^k. Mean luminance {:.4f} at -m 4 and {:.4f} "
        "at -m 100 (noise {} and {}): the difference is the light of the fifth and later "
        "bounces, which roulette keeps in expectation (the survivors carry it, divided by "
        "0.65 per bounce) while it ends most paths early.",
        s.scene, list,
        double(m100.stats.rays) / double(m100.stats.samples) /
            (double(m4.stats.rays) / double(m4.stats.samples)),
        m4.image.meanLuminance, m100.image.meanLuminance, noiseText(m4.image),
        noiseText(m100.image));
}

std::string adaptive(const SceneShots& s) {
    const ShotResult& r = s.shots[0];
    const ImageMeasures& m = r.image;
    return fmt::format(
        "{}: at most {} samples per pixel, the pixels took {:.1f} on average (from {} to {}), "
        "so the render traced {:.0f} % of the samples the cap allows ({}). {:.0f} % of the lit "
        "pixels stopped before the cap: blue to green in the rate image where their samples "
        "agree, red where they disagree (soft shadows, corners lit only indirectly, edges) and "
        "the pixel ran to the cap. The {:.0f} % of the pixels that see nothing (black: every "
        "sample zero, so sigma = 0) stopped at the first check.",
        s.scene, r.spp, m.meanSpp, m.minSpp, m.maxSpp, 100 * m.meanSpp / r.spp, timing(r),
        100 * m.stoppedEarlyLit, 100 * m.blackFraction);
}

}  // namespace

std::vector<std::string> figureProse(const Figure& figure, const std::vector<SceneShots>& scenes) {
    std::vector<std::string> out;
    const std::string& k = figure.key;
    bool noiseFigure = k == "gi" || k == "spp" || k == "roulette";
    for (const SceneShots& s : scenes) {
        if (k == "normals") out.push_back(normals(s));
        if (k == "zero") out.push_back(zero(s));
        if (k == "hemisphere")
            out.push_back(fmt::format("{}: -H with {} camera rays per pixel: {}, noise {}.",
                                      s.scene, s.shots[0].spp, timing(s.shots[0]),
                                      noiseText(s.shots[0].image)));
        if (k == "lightrays") out.push_back(lightRays(s));
        if (k == "gi") out.push_back(gi(s));
        if (k == "bounce") out.push_back(bounce(s));
        if (k == "depth") out.push_back(depth(s));
        if (k == "spp") out.push_back(sweep(s));
        if (k == "roulette") out.push_back(roulette(s));
        if (k == "adaptive") out.push_back(adaptive(s));
    }
    if (noiseFigure || k == "hemisphere") out.back() += kNoiseDefinition;
    return out;
}

std::vector<std::string> directComparison(const std::vector<SceneShots>& hemisphere,
                                          const std::vector<SceneShots>& importance) {
    std::vector<std::string> out;
    for (size_t i = 0; i < hemisphere.size() && i < importance.size(); ++i)
        out.push_back(directCompare(hemisphere[i], importance[i]));
    return out;
}

std::vector<std::string> timingProse(const std::vector<TimingRow>& rows, double floorSeconds) {
    std::vector<std::string> out;
    out.push_back(fmt::format(
        "Every timed render took at least {} s, above the timer's noise: where one frame at 1 "
        "sample per pixel was faster the command renders more samples (-s), and brute force "
        "renders a band of the frame (--crop); the last column scales each measured rate to "
        "one full 800x600 frame at 1 sample per pixel.",
        fixed(floorSeconds, 2)));
    for (size_t i = 0; i + 2 < rows.size(); i += 3) {  // Embree, reference BVH, none
        const TimingRow &e = rows[i], &b = rows[i + 1], &n = rows[i + 2];
        out.push_back(fmt::format(
            "{} ({} primitives): without a BVH a frame would take {} s, with the course's BVH {} "
            "s ({:.0f} times faster; building it took {:.3g} s) and with Embree {} s. Brute force "
            "costs a ray every primitive, {:.3g} Mrays/s here, while a BVH visits a few boxes "
            "and leaves, {:.3g} Mrays/s: the gap grows with the number of primitives.",
            e.mesh, e.primitives, fixed(n.frameSeconds(), 1), fixed(b.frameSeconds(), 3),
            n.frameSeconds() / b.frameSeconds(), b.shot.buildSeconds, fixed(e.frameSeconds(), 3),
            mrays(n.shot), mrays(b.shot)));
    }
    return out;
}

}  // namespace kiln::cs184
