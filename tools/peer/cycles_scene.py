# Builds a peer-benchmark scene in Blender's Cycles from the same description kiln reads, renders it
# with exactly N samples, a 1-pixel box filter, no denoising, no adaptive sampling, no clamping and a
# fixed seed, and writes a linear EXR. Run by tools/peer_bench.py:
#   blender -b --factory-startup --python tools/peer/cycles_scene.py -- SCENE.json SPP THREADS OUT.exr
# It prints "kiln-peer: scene_seconds S" (the scene built in Python: OBJ import, nodes) and
# "kiln-peer: render_seconds S" (the render call: Cycles' scene sync, BVH build, sampling, EXR write);
# run with --debug-cycles, Cycles itself prints "Rendered N samples in S seconds" (the sampling).
import json
import math
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_principled import principled_material  # noqa: E402


def args():
    argv = sys.argv[sys.argv.index("--") + 1:]
    seed = int(argv[4]) if len(argv) > 4 else 7
    return json.load(open(argv[0])), int(argv[1]), int(argv[2]), argv[3], seed


def clear():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def make_material(name, m, distribution="BECKMANN"):
    """kiln's material in Cycles: Lambert as a Diffuse BSDF (roughness 0), kiln's microfacet conductor as
    a Glossy BSDF with the same distribution (Cycles squares its roughness: alpha = r^2) and colour 1
    (Cycles' Glossy BSDF has no Fresnel; the scenes use eta 0, where kiln's conductor Fresnel is 1),
    emission as an Emission shader of strength 1 (its colour is the radiance, kiln's units); a principled
    material as cycles_principled.py maps it."""
    if "principled" in m:
        return principled_material(name, m)
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.remove(nodes["Principled BSDF"])
    if "emission" in m:
        node = nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = (*m["emission"], 1.0)
        node.inputs["Strength"].default_value = 1.0
        socket = node.outputs["Emission"]
    elif "alpha" in m:
        node = nodes.new("ShaderNodeBsdfGlossy")
        node.distribution = distribution
        node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        node.inputs["Roughness"].default_value = math.sqrt(m["alpha"])
        socket = node.outputs["BSDF"]
    else:
        node = nodes.new("ShaderNodeBsdfDiffuse")
        node.inputs["Color"].default_value = (*m["albedo"], 1.0)
        node.inputs["Roughness"].default_value = 0.0  # Lambert
        socket = node.outputs["BSDF"]
    links.new(socket, nodes["Material Output"].inputs["Surface"])
    return mat


def has_normals(path):
    with open(path) as f:
        return any(line.startswith("vn ") for line in f)


def import_mesh(path, matrix, material, distribution):
    # forward Y, up Z: the file's coordinates as they are (kiln's scene space, Y up), so the
    # camera and the environment mapping below use kiln's numbers unchanged.
    bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    obj = bpy.context.selected_objects[0]
    from mathutils import Matrix
    obj.matrix_world = Matrix([matrix[0:4], matrix[4:8], matrix[8:12], matrix[12:16]])
    obj.data.materials.clear()
    obj.data.materials.append(make_material(obj.name, material, distribution))
    # kiln interpolates the file's vertex normals and shades flat where the file has none
    smooth = has_normals(path)
    for poly in obj.data.polygons:
        poly.use_smooth = smooth


def add_quad(q):
    mesh = bpy.data.meshes.new(q["name"])
    mesh.from_pydata([tuple(c) for c in q["corners"]], [], [(0, 1, 2, 3)])
    mesh.materials.append(make_material(q["name"], q["material"]))
    obj = bpy.data.objects.new(q["name"], mesh)
    bpy.context.scene.collection.objects.link(obj)


def add_camera(cam, width, height):
    from mathutils import Matrix, Vector
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL" if width >= height else "HORIZONTAL"
    data.angle = math.radians(cam["fov"])  # kiln: the .kiln fov is the narrower image axis
    obj = bpy.data.objects.new("camera", data)
    bpy.context.scene.collection.objects.link(obj)
    pos, look, up = Vector(cam["position"]), Vector(cam["look_at"]), Vector(cam["up"])
    forward = (look - pos).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rot = Matrix((right, true_up, -forward)).transposed()  # columns: camera x, y, z
    obj.matrix_world = Matrix.Translation(pos) @ rot.to_4x4()
    bpy.context.scene.camera = obj


def add_environment(path, strength):
    # kiln's lat-long lookup, built from nodes so the orientation is kiln's by construction:
    # u = 0.5 + atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi (v = 0 the top row), bilinear between
    # texel centres as kiln's TextureSystem lookup (checked: a 16-spp Cycles render is 0.0068 relMSE
    # from kiln's 1024-spp reference with "Linear", 0.0108 with "Closest").
    world = bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nodes, links = nt.nodes, nt.links
    coords = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coords.outputs["Generated"], split.inputs["Vector"])

    def math_node(op, a, b=None):
        n = nodes.new("ShaderNodeMath")
        n.operation = op
        for i, v in enumerate((a, b)):
            if v is None:
                continue
            if isinstance(v, float):
                n.inputs[i].default_value = v
            else:
                links.new(v, n.inputs[i])
        return n.outputs[0]

    neg_z = math_node("MULTIPLY", split.outputs["Z"], -1.0)
    u = math_node("ADD", math_node("DIVIDE", math_node("ARCTAN2", split.outputs["X"], neg_z),
                                   2 * math.pi), 0.5)
    v = math_node("DIVIDE", math_node("ARCCOSINE", split.outputs["Y"]), math.pi)
    uv = nodes.new("ShaderNodeCombineXYZ")
    links.new(u, uv.inputs["X"])
    links.new(math_node("SUBTRACT", 1.0, v), uv.inputs["Y"])
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(path)
    tex.image.colorspace_settings.name = "Linear"
    tex.interpolation = "Linear"
    tex.extension = "EXTEND"
    links.new(uv.outputs["Vector"], tex.inputs["Vector"])
    background = nodes["Background"] if "Background" in nodes else nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = strength
    links.new(tex.outputs["Color"], background.inputs["Color"])
    output = nodes.get("World Output") or nodes.new("ShaderNodeOutputWorld")
    links.new(background.outputs["Background"], output.inputs["Surface"])
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 1024


def black_world():
    # No world light: the factory-empty file has no world, which Cycles renders black; say so.
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    bpy.context.scene.world = world


def configure(scene_desc, spp, threads, out, seed):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.seed = seed
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    bounces = scene_desc["max_bounces"]
    c.max_bounces = bounces
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = bounces
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x, scene.render.resolution_y = scene_desc["resolution"]
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    scene.render.filepath = out
    scene.render.use_persistent_data = False


def main():
    desc, spp, threads, out, seed = args()
    scene_start = time.perf_counter()
    clear()
    distribution = desc.get("microfacet", "beckmann").upper()  # kiln --microfacet: beckmann, ggx
    for mesh in desc["meshes"]:
        import_mesh(mesh["file"], mesh["matrix"], mesh["material"], distribution)
    for q in desc.get("quads", []):
        add_quad(q)
    add_camera(desc["camera"], *desc["resolution"])
    if desc.get("environment"):
        add_environment(desc["environment"], desc.get("environment_strength", 1.0))
    else:
        black_world()
    configure(desc, spp, threads, out, seed)
    start = time.perf_counter()
    print("kiln-peer: scene_seconds %.4f" % (start - scene_start), flush=True)
    bpy.ops.render.render(write_still=True)
    print("kiln-peer: render_seconds %.4f" % (time.perf_counter() - start), flush=True)


if __name__ == "__main__":  # Blender runs a --python script as __main__
    main()
