// Batch job files (JSON, docs/farm.md): scenes x cameras x frames x settings, expanded into one
// RenderTask per output, with {scene} {camera} {frame} {settings} {index} in the output name.
#pragma once

#include <string>
#include <vector>

#include "renderer/farm/render_task.h"

namespace kiln::farm {

// Where in the job file some of a task's render options come from ("job.json: cameras[1]: 'up'"),
// so a check of them can name the entry and the field.
struct ArgSource {
    std::string where;
    std::vector<std::string> args;
};
// A task's options part by part, and the task in words ("job.json: the render of scene 'a.obj',
// camera 'orbit', frame 3, settings 'hi'").
struct TaskOrigin {
    std::vector<ArgSource> sources;
    std::string label;
};

// Reads and expands FILE. Paths in it are relative to its folder. Throws FarmInputError naming
// the file and the problem (bad JSON, unknown key, wrong type, missing scene, clashing outputs).
// origins, when given, receives one TaskOrigin per task.
std::vector<RenderTask> readJobFile(const std::string& path,
                                    std::vector<TaskOrigin>* origins = nullptr);

// The same from JSON text; `folder` resolves relative paths, `name` is used in errors.
std::vector<RenderTask> expandJobText(const std::string& text, const std::string& folder,
                                      const std::string& name,
                                      std::vector<TaskOrigin>* origins = nullptr);

// "{scene}_{frame:04}" with the variables filled in; throws FarmInputError on an unknown one.
struct OutputVariables {
    std::string scene, camera, settings;
    int frame = 0, index = 0;
};
std::string expandOutputName(const std::string& pattern, const OutputVariables& vars);

}  // namespace kiln::farm
