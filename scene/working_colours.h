// Colours files give as linear values (.kiln, COLLADA, glTF, CGL, material overrides, vertex
// colours, the default rig) are linear Rec.709 unless the file says otherwise; kiln renders in the
// config's scene_linear (color/working_space.h), so they are converted once, after loading.
// sRGB-encoded colour is already decoded into scene_linear by OCIO (color/srgb_decode.h), and
// environment maps are read into it (color/image_input.h): neither is touched here.
#pragma once

#include "scene/scene.h"

namespace kiln {

// Does nothing when the working space is linear Rec.709 (bit-identical images).
void convertColoursToWorkingSpace(Scene& scene);

}  // namespace kiln
