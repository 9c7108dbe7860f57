"""kiln, a batch path tracer, from Python: load a scene once, render it any number of times
through kiln's RenderJob, look at the beauty and AOVs as numpy arrays, write EXR + PNG exactly
as `kiln render` does. docs/python.md walks through it."""

import os as _os

from ._kiln import (
    Image,
    RenderOptions,
    Scene,
    SceneError,
    SceneWarning,
    __version__,
    _set_bundled_config,
    crosscheck,
    load,
    render,
    set_log_level,
)

# Installed (cmake --install), the package carries the OCIO config the previews go through; the
# build tree's module uses the source tree's, as the build tree's kiln binary does. $OCIO wins.
_config = _os.path.join(_os.path.dirname(__file__), "config.ocio")
if _os.path.isfile(_config):
    _set_bundled_config(_config)

for _name in ("Image", "RenderOptions", "Scene", "SceneError"):
    globals()[_name].__module__ = "kiln"

__all__ = [
    "Image",
    "RenderOptions",
    "Scene",
    "SceneError",
    "SceneWarning",
    "__version__",
    "crosscheck",
    "load",
    "render",
    "set_log_level",
]
