// The Python module's C++ side, free of Python: a scene loaded once with the accelerators built
// for it, renders of it through RenderJob exactly as kiln render sets them up (render_command.h),
// and the image they leave. python/module.cpp binds these to Python.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "color/image_output.h"
#include "renderer/cli/render_command.h"
#include "renderer/render_loop.h"
#include "renderer/validation/crosscheck.h"
#include "scene/scene.h"

namespace kiln::python {

// kiln render's parser: every option declared into c.
ArgParser renderParser(RenderCommand& c);

// The options of kiln render the arguments give (load options first, then the render's; the scene
// path is not among them). Throws UsageError with kiln render's message.
RenderCommand parseRenderArguments(const std::vector<std::string>& args);

// A scene loaded once and rendered any number of times: each render applies its camera options
// to the scene's camera and puts it back after, so renders of one scene take turns.
class LoadedScene {
  public:
    // Loads path with the load options the arguments give (kiln render's Scene group). Throws
    // SceneError (bad input) or UsageError (bad option).
    LoadedScene(std::string path, std::vector<std::string> loadArgs);

    const std::string& path() const { return path_; }
    const std::vector<std::string>& loadArguments() const { return loadArgs_; }
    const Scene& scene() const { return scene_; }
    // kiln info --json of the scene as loaded.
    const std::string& infoJson() const { return info_; }
    // The accelerators built so far: description, build seconds, bytes.
    std::vector<AcceleratorStats> accelerators();

    // Renders through one RenderJob; control's cancel and tileDone reach the tile loop.
    struct Result {
        Film film{0, 0};
        RenderStats stats;
        Metadata metadata;
        RenderCommand command;
    };
    Result render(RenderCommand c, const RenderControl& control);

    // kiln crosscheck: Embree and the reference BVH of the choice, raysPerCategory each of camera,
    // random, secondary and shadow rays.
    Json crosscheck(const AcceleratorChoice& choice, size_t raysPerCategory, uint64_t seed);

    // The threads inside a render or crosscheck of this scene: one asked from a render's own
    // progress callback (the same thread) would wait for itself, and is refused instead.
    class Caller {
      public:
        explicit Caller(LoadedScene& scene);  // throws std::logic_error for a nested render
        ~Caller();
        Caller(const Caller&) = delete;
        Caller& operator=(const Caller&) = delete;

      private:
        LoadedScene& scene_;
    };

  private:
    std::mutex callersMutex_;
    std::vector<std::thread::id> callers_;

    // The accelerator of this choice, built on first use and kept (brute force: made again for
    // each render, its time estimate depends on the render). Called with mutex_ held.
    const Accelerator& accelerator(const AcceleratorChoice& choice, const RenderJobOptions* job);

    std::string path_;
    std::vector<std::string> loadArgs_;
    Scene scene_;
    Bounds3 bounds_;  // scene_.storedBounds(), for each render's camera options
    std::string info_;
    std::mutex mutex_;       // held by a render or crosscheck: the camera is theirs meanwhile
    std::mutex accelMutex_;  // the map (listed while a render runs, e.g. from its callback)
    std::map<std::string, std::unique_ptr<Accelerator>> accelerators_;
};

// Every layer of the film in the EXR's order and channel values, filled in one pass: layer l's
// pixels are values[offsets[l] ...], height x width x its channel count, row by row.
struct FilledLayers {
    std::vector<ExrLayer> layers;
    std::vector<size_t> offsets;
    std::vector<float> values;
};
// With `denoised` (a render with --denoise, its frame denoised): the beauty's R, G, B are the
// denoised image, the raw one the layer "noisy", and each --denoise-aovs layer likewise (its raw
// one "noisy.LAYER"), as the EXR kiln render --denoise writes holds them.
FilledLayers fillLayers(const Film& film, const DenoisedFrame* denoised = nullptr);

// Writes OUT.exr, OUT.png (and the heat map with -a, --noise-threshold or --heatmap) as kiln
// render -o OUT does: the paths written. Throws std::runtime_error naming every failed write,
// UsageError when the directory does not exist.
OutputPaths writeImage(const LoadedScene::Result& image, const std::string& output,
                       std::string& heatPath, const DenoisedFrame* denoised = nullptr);

}  // namespace kiln::python
