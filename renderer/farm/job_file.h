// Batch job files (JSON, docs/farm.md): scenes x cameras x frames x settings, expanded into one
// RenderTask per output, with {scene} {camera} {frame} {settings} {index} in the output name.
#pragma once

#include <string>
#include <vector>

#include "renderer/farm/render_task.h"

namespace kiln::farm {

// Reads and expands FILE. Paths in it are relative to its folder. Throws FarmInputError naming
// the file and the problem (bad JSON, unknown key, wrong type, missing scene, clashing outputs).
std::vector<RenderTask> readJobFile(const std::string& path);

// The same from JSON text; `folder` resolves relative paths, `name` is used in errors.
std::vector<RenderTask> expandJobText(const std::string& text, const std::string& folder,
                                      const std::string& name);

// "{scene}_{frame:04}" with the variables filled in; throws FarmInputError on an unknown one.
struct OutputVariables {
    std::string scene, camera, settings;
    int frame = 0, index = 0;
};
std::string expandOutputName(const std::string& pattern, const OutputVariables& vars);

}  // namespace kiln::farm
