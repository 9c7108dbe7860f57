#include "python/session.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

#include "renderer/core/log.h"
#include "renderer/denoise_film.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"

namespace kiln::python {
namespace {

// The key of an accelerator in the scene's cache: everything its build depends on.
std::string acceleratorKey(const AcceleratorChoice& c) {
    if (c.kind == AcceleratorKind::Reference)
        return fmt::format("reference {} {}", toString(c.reference.split), c.reference.maxLeafSize);
    return fmt::format("embree {} robust {} compact {} watertight {}", toString(c.embree.quality),
                       c.embree.robust, c.embree.compact, c.embree.watertight);
}

// The scene's camera put back however a render ends.
class CameraRestore {
  public:
    explicit CameraRestore(Scene& scene) : scene_(scene), saved_(scene.camera) {}
    ~CameraRestore() { scene_.camera = saved_; }
    CameraRestore(const CameraRestore&) = delete;
    CameraRestore& operator=(const CameraRestore&) = delete;

  private:
    Scene& scene_;
    Camera saved_;
};

}  // namespace

ArgParser renderParser(RenderCommand& c) {
    ArgParser parser("render", "SCENE [options]   (writes OUT.exr and OUT.png)");
    addRenderOptions(parser, c);
    return parser;
}

RenderCommand parseRenderArguments(const std::vector<std::string>& args) {
    RenderCommand c;
    ArgParser parser = renderParser(c);
    std::vector<std::string> positional = parser.parse(args);
    if (!positional.empty()) throw UsageError("unexpected argument '" + positional.front() + "'");
    return c;
}

LoadedScene::LoadedScene(std::string path, std::vector<std::string> loadArgs)
    : path_(std::move(path)), loadArgs_(std::move(loadArgs)) {
    RenderCommand c = parseRenderArguments(loadArgs_);
    scene_ = loadScene(path_, c.load);
    bounds_ = scene_.storedBounds();
    info_ = sceneInfoJson(scene_);
}

std::vector<AcceleratorStats> LoadedScene::accelerators() {
    std::lock_guard lock(accelMutex_);
    std::vector<AcceleratorStats> out;
    for (const auto& [key, accel] : accelerators_) out.push_back(accel->stats());
    return out;
}

LoadedScene::Caller::Caller(LoadedScene& scene) : scene_(scene) {
    std::lock_guard lock(scene.callersMutex_);
    auto& callers = scene.callers_;
    if (std::find(callers.begin(), callers.end(), std::this_thread::get_id()) != callers.end())
        throw std::logic_error(scene.path_ +
                               ": this thread is rendering the scene already (a render from "
                               "its own progress callback would wait for itself)");
    callers.push_back(std::this_thread::get_id());
}

LoadedScene::Caller::~Caller() {
    std::lock_guard lock(scene_.callersMutex_);
    auto& callers = scene_.callers_;
    callers.erase(std::find(callers.begin(), callers.end(), std::this_thread::get_id()));
}

const Accelerator& LoadedScene::accelerator(const AcceleratorChoice& choice,
                                            const RenderJobOptions* job) {
    std::string key =
        choice.kind == AcceleratorKind::BruteForce ? "brute force" : acceleratorKey(choice);
    {
        std::lock_guard lock(accelMutex_);
        auto found = accelerators_.find(key);
        if (found != accelerators_.end() && choice.kind != AcceleratorKind::BruteForce)
            return *found->second;
    }
    std::unique_ptr<Accelerator> built = choice.build(scene_, job);  // may refuse: nothing kept
    std::lock_guard lock(accelMutex_);
    std::unique_ptr<Accelerator>& slot = accelerators_[key];
    slot = std::move(built);
    return *slot;
}

LoadedScene::Result LoadedScene::render(RenderCommand c, const RenderControl& control) {
    RenderJobOptions options = renderJobOptions(c);
    options.settings.progress = false;  // no bar on stderr: the caller has tileDone
    checkColour(c);
    checkFilmFits(options, false);  // the image's numpy layers are about the EXR write's size
    std::lock_guard lock(mutex_);
    CameraRestore restore(scene_);
    applyCameraOptions(scene_, c, bounds_);
    const Accelerator& accel = accelerator(c.accel, &options);
    RenderJob job(scene_, accel, options);
    warnHemisphereBlind(job, path_);
    warnIdleOptions(job, c);
    addSceneToOutputs(c, scene_, options);
    Result result;
    result.film = job.makeFilm();
    result.stats = job.render(result.film, control);
    result.metadata = renderMetadata(job, c, path_, result.stats, result.film);
    result.command = std::move(c);
    return result;
}

Json LoadedScene::crosscheck(const AcceleratorChoice& choice, size_t raysPerCategory,
                             uint64_t seed) {
    std::lock_guard lock(mutex_);
    AcceleratorChoice embree = choice, reference = choice;
    embree.kind = AcceleratorKind::Embree;
    reference.kind = AcceleratorKind::Reference;
    const Accelerator& a = accelerator(embree, nullptr);
    const Accelerator& b = accelerator(reference, nullptr);
    return crosscheckJson(kiln::crosscheck(scene_, a, b, raysPerCategory, seed), path_);
}

namespace {

// Layer `name`'s first three channels become `colours`; the raw ones are appended as the layer
// "noisy" (the beauty's) or "noisy.NAME", as the EXR of kiln render --denoise holds them.
void substituteDenoised(FilledLayers& out, size_t pixels, const std::string& name,
                        const std::vector<Color>& colours) {
    for (size_t l = 0; l < out.layers.size(); ++l) {
        if (out.layers[l].name != name) continue;
        const size_t n = out.layers[l].channels.size();
        std::vector<float> raw(pixels * 3);
        float* values = out.values.data() + out.offsets[l];
        for (size_t p = 0; p < pixels; ++p)
            for (size_t c = 0; c < 3; ++c) {
                raw[3 * p + c] = values[p * n + c];
                values[p * n + c] = colours[p][int(c)];
            }
        out.offsets.push_back(out.values.size());
        out.values.insert(out.values.end(), raw.begin(), raw.end());
        out.layers.push_back({name.empty() ? "noisy" : "noisy." + name, {"R", "G", "B"}, 0});
        return;
    }
}

}  // namespace

FilledLayers fillLayers(const Film& film, const DenoisedFrame* denoised) {
    FilledLayers out;
    out.layers = exrLayers(film);
    const size_t pixels = size_t(film.width()) * size_t(film.height());
    size_t total = 0;
    for (const ExrLayer& layer : out.layers) {
        out.offsets.push_back(total);
        total += pixels * layer.channels.size();
    }
    out.values.resize(total);
    tbb::parallel_for(0, film.height(), [&](int y) {
        std::vector<float> px;
        for (int x = 0; x < film.width(); ++x) {
            exrPixel(film, x, y, px);
            const size_t pixel = size_t(y) * size_t(film.width()) + size_t(x);
            for (size_t l = 0; l < out.layers.size(); ++l) {
                const size_t n = out.layers[l].channels.size();
                std::copy_n(px.data() + out.layers[l].first, n,
                            out.values.data() + out.offsets[l] + pixel * n);
            }
        }
    });
    if (!denoised) return out;
    substituteDenoised(out, pixels, "", *denoised->exr.denoised);
    for (const auto& [name, colours] : denoised->exr.denoisedLayers)
        substituteDenoised(out, pixels, name, *colours);
    return out;
}

OutputPaths writeImage(const LoadedScene::Result& image, const std::string& output,
                       std::string& heatPath, const DenoisedFrame* denoised) {
    RenderCommand c = image.command;
    c.output = output;
    OutputPaths out = outputPaths(c, image.metadata.at("scene"));
    std::string errors;
    writeOutputs(
        c, out, image.film, image.metadata, heatPath,
        [&errors](const std::string& e) { errors += (errors.empty() ? "" : "; ") + e; }, nullptr,
        denoised);
    if (!errors.empty()) throw std::runtime_error(errors);
    return out;
}

}  // namespace kiln::python
