#include "renderer/cli/render_options.h"

#include <cmath>

namespace kiln {

namespace {
// --emitters: emissive meshes as lights, or as the CS184 program treats them.
enum class EmitterRule { Lights, Camera };
}  // namespace

template <>
struct EnumNames<EmitterRule> {
    static constexpr std::pair<EmitterRule, const char*> table[] = {
        {EmitterRule::Lights, "lights"}, {EmitterRule::Camera, "camera"}};
};

namespace {

void addTextureCacheOption(ArgParser& parser, LoadOptions& load) {
    parser.option("texture-cache-mb", "", 1, "MB",
                  "memory the texture cache may hold, in MiB (default 256): a scene with more "
                  "texture data than this renders in fixed memory, re-reading tiles",
                  [&load](const std::vector<std::string>& v) {
                      double mb = ArgParser::toDouble("--texture-cache-mb", v[0]);
                      if (!(mb >= 1 && mb <= 1048576))
                          throw UsageError("--texture-cache-mb must be in [1, 1048576]");
                      load.textureCacheMb = float(mb);
                  });
}

void addEnvironmentOptions(ArgParser& parser, LoadOptions& load) {
    parser.option("env-rotate", "", 1, "DEG",
                  "turn the environment map about the up axis, counterclockwise seen from above",
                  [&load](const std::vector<std::string>& v) {
                      double deg = ArgParser::toDouble("--env-rotate", v[0]);
                      if (!(std::abs(deg) <= 36000))
                          throw UsageError("--env-rotate must be in [-36000, 36000] degrees");
                      load.environmentRotationDeg = float(std::fmod(deg, 360.0));
                  });
    parser.option("env-strength", "", 1, "X", "multiply the environment map's radiance by X",
                  [&load](const std::vector<std::string>& v) {
                      double x = ArgParser::toDouble("--env-strength", v[0]);
                      if (!(x >= 0 && x <= 1e6))
                          throw UsageError("--env-strength must be in [0, 1e6]");
                      load.environmentScale = float(x);
                  });
}

}  // namespace

void addLoadOptions(ArgParser& parser, LoadOptions& load) {
    OptionGroup group(parser, "Scene");
    parser.enumOption("camera",
                      "the file's camera as written, or the CS184 course framing (default: course "
                      "framing for Z-up COLLADA)",
                      load.cameraRule);
    parser.option("env", "e", 1, "MAP.exr", "add a lat-long environment light (CS184's -e)",
                  [&load](const std::vector<std::string>& v) { load.environmentMap = v[0]; });
    parser.option("material-override", "", 1, "FILE_OR_SPEC",
                  "replace every material that does not emit: clay (Lambert grey 0.5), "
                  "lambertian:G or lambertian:R,G,B, or a .kiln file's <material> (FILE or "
                  "FILE:NAME)",
                  [&load](const std::vector<std::string>& v) {
                      parseMaterialOverride(v[0]);  // a bad spec fails here, before loading
                      load.materialOverride = v[0];
                  });
    addTextureCacheOption(parser, load);
    addEnvironmentOptions(parser, load);
}

void addOutputNameOptions(ArgParser& parser, std::string& output, PathOptions& path) {
    OptionGroup group(parser, "Output");
    parser.option("output", "", 1, "OUT",
                  "output base name: OUT.exr and OUT.png (default: scene name)",
                  [&output](const std::vector<std::string>& v) { output = v[0]; });
    parser.option("accumulate", "o", 1, "0|1|OUT",
                  "CS184's accumulate-bounces switch: -o 0 keeps only light that bounced "
                  "exactly -m times (as --bounce-only), -o 1 all bounces (default); any other "
                  "value is the output base name, as --output (an output named 0 or 1: --output 0)",
                  [&output, &path](const std::vector<std::string>& v) {
                      if (v[0] == "0" || v[0] == "1")
                          path.accumulateBounces = v[0] == "1";
                      else
                          output = v[0];
                  });
}

void addEmitterOption(ArgParser& parser, LoadOptions& load, PathOptions& path) {
    OptionGroup group(parser, "Scene");
    parser.enumOption<EmitterRule>(
        "emitters",
        "emissive meshes: lights (default, physically right) or camera: the CS184 "
        "program's behaviour, seen by camera and -H rays only, lighting nothing "
        "(area lights stay lights)",
        [&load, &path](EmitterRule rule) {
            load.emissiveMeshLights = path.unsampledEmittersLight = rule == EmitterRule::Lights;
        });
}

void addExposureOption(ArgParser& parser, float& stops) {
    OptionGroup group(parser, "Output");
    parser.option("exposure", "", 1, "STOPS",
                  "scale the preview's light by 2^STOPS before the display transform (the EXR "
                  "keeps the rendered values)",
                  [&stops](const std::vector<std::string>& v) {
                      double value = ArgParser::toDouble("--exposure", v[0]);
                      if (std::abs(value) > 64) throw UsageError("--exposure must be in [-64, 64]");
                      stops = float(value);
                  });
}

namespace {

void addImageOptions(ArgParser& parser, RenderJobArgs& a) {
    RenderSettings& s = a.job.settings;
    OptionGroup group(parser, "Image");
    parser.option("resolution", "r", 2, "W H", "image size (default 800 600)",
                  [&s](const std::vector<std::string>& v) {
                      s.width = ArgParser::toInt("-r", v[0], 1, 32768);
                      s.height = ArgParser::toInt("-r", v[1], 1, 32768);
                  });
    parser.option(
        "crop", "", 4, "X0 X1 Y0 Y1",
        "render only this window of the image, as fractions of its width and height (pbrt's "
        "crop window); the EXR keeps the full image as its display window",
        [&a](const std::vector<std::string>& v) {
            double* c = a.crop;
            for (int i = 0; i < 4; ++i) c[i] = ArgParser::toDouble("--crop", v[size_t(i)]);
            if (!(c[0] >= 0 && c[0] < c[1] && c[1] <= 1 && c[2] >= 0 && c[2] < c[3] && c[3] <= 1))
                throw UsageError(
                    "--crop takes X0 X1 Y0 Y1 with 0 <= X0 < X1 <= 1 and 0 <= Y0 < Y1 <= 1");
        });
    parser.group("Sampling");
    parser.intOption("spp", "s", "camera samples per pixel (default 1)", s.spp, 1, 1 << 20);
    parser.intOption("threads", "t", "worker threads (default: all cores)", s.threads, 1, 4096);
    parser.intOption("tile", "", "tile size in pixels (default 32)", s.tileSize, 1, 4096);
    parser.enumOption("sampler",
                      "sample values: shuffled, Owen-scrambled Sobol points (default; "
                      "stratified over each pixel's samples) or independent random numbers",
                      s.sampler);
    parser.option("seed", "", 1, "N", "random seed (default 0)",
                  [&s](const std::vector<std::string>& v) {
                      s.seed = uint64_t(ArgParser::toInt("--seed", v[0], 0, 2147483647));
                  });
    parser.option("adaptive", "a", 2, "BATCH TOL",
                  "adaptive sampling: test every BATCH samples, stop at "
                  "1.96 sigma/sqrt(n) <= TOL mu (CS184; -s is the maximum)",
                  [&s](const std::vector<std::string>& v) {
                      s.adaptiveBatch = ArgParser::toInt("-a", v[0], 1, 1 << 20);
                      s.adaptiveTolerance = float(ArgParser::toDouble("-a", v[1]));
                      if (!(s.adaptiveTolerance > 0)) throw UsageError("-a tolerance must be > 0");
                  });
    parser.option("noise-threshold", "", 1, "T",
                  "adaptive sampling by a noise threshold (as Cycles' adaptive threshold): a "
                  "pixel stops once the relative standard error of its mean is <= T, tested "
                  "every --adaptive-min-spp samples (-s is the maximum)",
                  [&s](const std::vector<std::string>& v) {
                      s.noiseThreshold = float(ArgParser::toDouble("--noise-threshold", v[0]));
                      if (!(s.noiseThreshold > 0 && s.noiseThreshold < 1e6f))
                          throw UsageError("--noise-threshold must be in (0, 1e6)");
                  });
    parser.intOption("adaptive-min-spp", "",
                     "samples before the noise threshold is first tested, and between tests "
                     "(default 16)",
                     s.adaptiveMinSpp, 2, 1 << 20);
}

void addTransportOptions(ArgParser& parser, RenderJobArgs& a) {
    PathOptions& p = a.job.path;
    OptionGroup group(parser, "Transport");
    parser.option("integrator", "i", 1, "NAME",
                  "light transport: " + enumChoices<IntegratorKind>() + " (default path)",
                  [&a](const std::vector<std::string>& v) {
                      auto kind = parseEnum<IntegratorKind>(v[0]);
                      if (!kind)
                          throw UsageError("unknown integrator '" + v[0] +
                                           "' (known: " + enumChoices<IntegratorKind>() + ")");
                      a.job.integrator = *kind;
                  });
    parser.intOption("max-depth", "m",
                     "CS184 depth: 0 emission only, 1 direct lighting, >= 2 global illumination "
                     "(default 5)",
                     p.maxDepth, 0, 100000);
    parser.intOption(
        "light-samples", "l",
        "light samples per shading point (default 4 when an environment map lights the "
        "scene, else 1)",
        p.lightSamples, 1, 65536);
    parser.option(
        "hemisphere", "H", 0, "",
        "direct light by uniform hemisphere sampling (same as --sampling hemisphere)",
        [&p](const std::vector<std::string>&) { p.sampling = DirectSampling::Hemisphere; });
    parser.enumOption("sampling", "direct lighting strategy (default mis)", p.sampling);
    parser.enumOption("heuristic", "MIS heuristic (default power)", p.heuristic);
    parser.enumOption("rr",
                      "Russian roulette (default throughput; fixed = CS184's constant "
                      "continuation)",
                      p.roulette);
    parser.option("rr-continue", "", 1, "P",
                  "continuation probability of --rr fixed (default 0.65)",
                  [&p](const std::vector<std::string>& v) {
                      p.fixedContinuation = float(ArgParser::toDouble("--rr-continue", v[0]));
                      if (!(p.fixedContinuation > 0 && p.fixedContinuation <= 1))
                          throw UsageError("--rr-continue must be in (0, 1]");
                  });
    parser.intOption("rr-start", "",
                     "--rr throughput plays roulette once a path has bounced N times (default 5)",
                     p.rouletteMinBounces, 1, 100000);
    parser.option("bounce-only", "", 0, "",
                  "keep only light that bounced exactly -m times (accumulate bounces off)",
                  [&p](const std::vector<std::string>&) { p.accumulateBounces = false; });
    parser.enumOption("microfacet", "microfacet distribution (default beckmann, as CS184)",
                      p.microfacet);
    parser.enumOption("guiding",
                      "path guiding of diffuse bounces, learnt before the render (default auto: "
                      "the render plan decides; not with -H)",
                      p.guiding);
    parser.enumOption("plan",
                      "auto (default): the path specialised for what the scene holds; "
                      "general: every feature on (the baseline the specialisations are checked "
                      "against)",
                      a.job.plan);
}

}  // namespace

uint32_t parseDenoisedAovs(const std::string& list) {
    try {
        return AovRequest::parseDenoised(list);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--denoise-aovs: ") + e.what());
    }
}

void RenderJobArgs::addOptions(ArgParser& parser) {
    addImageOptions(parser, *this);
    addTransportOptions(parser, *this);
    OptionGroup group(parser, "Output");
    parser.option("aov", "", 1, "LIST",
                  std::string("EXR layers beside the beauty, comma-separated: ") +
                      AovRequest::names() +
                      " (default: emission,direct,indirect,albedo,N,Z,samples,variance)",
                  [this](const std::vector<std::string>& v) { aovList = v[0]; });
}

RenderJobOptions RenderJobArgs::finish() const {
    RenderJobOptions out = job;
    RenderSettings& s = out.settings;
    if (crop[0] > 0 || crop[1] < 1 || crop[2] > 0 || crop[3] < 1) {
        // pbrt's rule: pixel bounds are the ceilings of the scaled fractions.
        auto at = [](double f, int n) { return int(std::ceil(f * double(n))); };
        s.regionX0 = at(crop[0], s.width), s.regionX1 = at(crop[1], s.width);
        s.regionY0 = at(crop[2], s.height), s.regionY1 = at(crop[3], s.height);
        if (s.regionX1 <= s.regionX0 || s.regionY1 <= s.regionY0)
            throw UsageError("--crop window holds no pixel at " + std::to_string(s.width) + "x" +
                             std::to_string(s.height));
    }
    if (out.path.guiding == GuideMode::On &&
        (out.path.sampling == DirectSampling::Hemisphere || out.integrator != IntegratorKind::Path))
        throw UsageError(
            "--guiding on guides the path integrator's bounces: not with -H or "
            "the normals integrator");
    if (s.adaptiveBatch > 0 && s.noiseThreshold > 0)
        throw UsageError("-a and --noise-threshold are two adaptive sampling rules: give one");
    try {
        out.aovs = AovRequest::parse(aovList, out.path.maxDepth);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--aov: ") + e.what());
    }
    return out;
}

}  // namespace kiln
