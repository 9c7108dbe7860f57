# Renders a glTF in Cycles as Blender's own glTF importer reads it (a Principled BSDF per material:
# what a Blender user gets from the asset) under a uniform white world of strength 1, with the
# camera, image size and bounces of a description kiln renders too (tools/make_principled_grid.py
# writes scenes/principled_grid/grid.json). Run by tools/principled_grid_compare.py:
#   blender -b --factory-startup --python tools/peer/cycles_gltf.py -- SCENE.json SPP THREADS OUT.exr
import json
import os
import sys

import bpy
import numpy

# Blender 3.4's glTF importer still says np.bool, which the numpy Debian ships has removed.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_scene import add_camera, clear, configure  # noqa: E402


def to_blender(v):
    # Blender's glTF importer turns glTF's Y-up into Blender's Z-up: (x, y, z) -> (x, -z, y).
    return [v[0], -v[2], v[1]]


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    desc, spp, threads, out = json.load(open(argv[0])), int(argv[1]), int(argv[2]), argv[3]
    clear()
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(desc["gltf"]))
    cam = dict(desc["camera"])
    for key in ("position", "look_at", "up"):
        cam[key] = to_blender(cam[key])
    add_camera(cam, *desc["resolution"])
    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world
    configure(desc, spp, threads, out, 7)
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main()
