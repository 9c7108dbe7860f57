// Checkpoints: the film's exact per-pixel state on disk (format in docs/long-renders.md), with the
// fingerprint of the scene, settings and kiln version it belongs to. kiln render --checkpoint-every
// and --resume, and kiln merge, read and write them here.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "color/image_output.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {

// What must be equal for two checkpoints to continue or combine: ordered (name, value) pairs.
using Fingerprint = std::vector<std::pair<std::string, std::string>>;

constexpr uint32_t kCheckpointFormat = 1;

// Everything in a checkpoint besides the film's buffers.
struct CheckpointInfo {
    Fingerprint fingerprint;
    AovRequest aovs;
    int fullWidth = 0, fullHeight = 0;
    int originX = 0, originY = 0, width = 0, height = 0;  // the region its film holds
    int sampleStart = 0, sampleEnd = 0;                   // the samples [start, end) it renders
    int filmScaleExponent = 0;  // its film's radiance scale (Film::setScaleExponent)
    bool complete = false;      // every pixel has them all
    // Totals over every run that added to it (a resumed render adds its own).
    uint64_t rays = 0, nonFiniteSamples = 0;
    double seconds = 0;
    Metadata metadata;  // the EXR's kiln: attributes, for kiln merge

    std::string regionText() const;  // "WxH+X+Y of FWxFH"
};

// The scene file's (and --env map's) name, size and CRC-32, and those of every other file the
// loaded scene was read from (Scene::inputFiles, file textures): a resume after an edit of an
// included mesh or a texture is refused, not blended. Reading them is the fingerprint's one cost
// that grows with the scene (25 ms for a 20 MB mesh), so a process that renders one loaded scene
// many times (kiln render-frames) reads them once per load and keeps them with the scene.
struct SceneFileIdentity {
    std::string scene, environmentMap;
    std::string inputs;  // "" for a scene read from its one file
};
SceneFileIdentity sceneFileIdentity(const std::string& scenePath, const LoadOptions& load,
                                    const Scene& scene);
// The same in two steps: the scene file's and the --env map's alone (inputs ""), which need no
// load, then the loaded scene's other files added.
SceneFileIdentity topFileIdentity(const std::string& scenePath, const LoadOptions& load);
SceneFileIdentity withInputIdentities(SceneFileIdentity top, const std::string& scenePath,
                                      const LoadOptions& load, const Scene& scene);
// How many times this process has read them (kiln render-frames reports it beside its loads).
uint64_t sceneChecksumCount();

// The scene's files (as above), the camera as framed, every option that changes a sample's value,
// and the kiln version. Not: spp, threads, tile size, region.
Fingerprint checkpointFingerprint(const RenderJob& job, const SceneFileIdentity& files,
                                  const LoadOptions& load);
// The same, the files read now.
Fingerprint checkpointFingerprint(const RenderJob& job, const std::string& scenePath,
                                  const LoadOptions& load);
// Its fields that the options and the top files (topFileIdentity) decide alone, in its order: a
// resume is checked against them before the scene is loaded (checkResumeBeforeLoad).
Fingerprint fingerprintBeforeLoad(const RenderJobOptions& options, const SceneFileIdentity& files,
                                  const LoadOptions& load);

// "" when equal, else one phrase naming the first difference ("max_depth is 5 in X, 8 here").
std::string fingerprintDifference(const Fingerprint& saved, const Fingerprint& here,
                                  const std::string& savedName);

// The info of a render of this job into film, as it stands.
CheckpointInfo checkpointInfo(const Fingerprint& fingerprint, const RenderJobOptions& options,
                              const Film& film, const RenderStats& totals, const Metadata& meta);

// Written through an AtomicFile: the previous checkpoint survives until this one is complete on
// disk. Throws std::runtime_error naming path.
void writeCheckpoint(const std::string& path, const CheckpointInfo& info, const Film& film);

// Reads only the header. Throws CheckpointError (not a checkpoint, unknown format, truncated).
CheckpointInfo readCheckpointInfo(const std::string& path);
// Reads the whole checkpoint and checks its checksum. Throws CheckpointError.
Film readCheckpoint(const std::string& path, CheckpointInfo& info);

// Adds the checkpoint's film into into (a film of a region holding the shard's), streaming: the
// shard is never whole in memory. Shards in order of their first sample (FirstSample). Throws
// CheckpointError; into is then partly merged.
void mergeCheckpoint(const std::string& path, Film& into, CheckpointInfo& info);

struct CheckpointError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace kiln
