# kiln's principled material, given by its .kiln attributes (docs/kiln-scene.md), as Cycles 3.4 nodes,
# for tools/peer/material_compare.py (through cycles_scene.py). What each input becomes:
# - base-color, metallic, roughness: the Principled BSDF's, distribution GGX (single scattering, as kiln).
# - ior, specular: Cycles' dielectric F0 is 0.08 Specular, kiln's specular ((ior - 1) / (ior + 1))^2;
#   IOR goes to Cycles' IOR (its transmission refracts and weighs Fresnel by it).
# - transmission: Transmission. attenuation-color/-distance: a Volume Absorption in the material's volume
#   output with sigma_a = -ln(colour) / distance per channel (Cycles: sigma_a = density (1 - colour)),
#   homogeneous (sampled analytically, as kiln's absorbing media).
# - subsurface 1 (kiln blends by its weight, Cycles scales the radius by it: only 0 or 1 map): Subsurface 1,
#   Subsurface Color = base-color (Cycles 3.4's walk albedo), method "Random Walk (Fixed Radius)", whose
#   extinction is 4 pi / radius (bssrdf_setup_radius); kiln's is 1 / (d s(A)) with d = subsurface-radius x
#   subsurface-scale and Chiang et al.'s s(A) = 1.9 - A + 3.5 (A - 0.8)^2 (integrators/subsurface.cpp), so
#   the radius given to Cycles is 4 pi d s(A): both walk media then have the same extinction. The single-
#   scattering albedo each derives from A is each renderer's own fit (Cycles 3.4: Wrenninge et al.'s).
# A material with "cycles_shader": "subsurface_node" is the walk alone in Cycles: a Subsurface Scattering
# node (no specular layer, no retro-reflection lobe, a plain Lambertian exit), the same walk medium.
import math

import bpy

KILN_DEFAULTS = {"metallic": 0.0, "specular": 1.0, "ior": 1.5, "transmission": 0.0, "subsurface": 0.0,
                 "subsurface-radius": [1.0, 0.2, 0.1], "subsurface-scale": 1.0,
                 "attenuation-color": [1.0, 1.0, 1.0], "attenuation-distance": math.inf}
SUPPORTED = set(KILN_DEFAULTS) | {"base-color", "roughness", "thickness"}


def walk_radius(p):
    """Cycles' fixed-radius walk radius for kiln's walk medium, per channel (see the head comment)."""
    d = [r * p["subsurface-scale"] for r in p["subsurface-radius"]]
    return [4 * math.pi * di * (1.9 - a + 3.5 * (a - 0.8) ** 2) for di, a in zip(d, p["base-color"])]


def absorption(p):
    """sigma_a per channel (kiln's scene/volume_media), or None where nothing is absorbed."""
    if p["transmission"] <= 0 or p.get("thickness", 0) <= 0 or math.isinf(p["attenuation-distance"]):
        return None
    return [-math.log(c) / p["attenuation-distance"] for c in p["attenuation-color"]]


def add_absorption(nodes, links, sigma_a, output):
    density = max(sigma_a)
    node = nodes.new("ShaderNodeVolumeAbsorption")
    node.inputs["Color"].default_value = (*[1 - s / density for s in sigma_a], 1.0)
    node.inputs["Density"].default_value = density
    links.new(node.outputs["Volume"], output.inputs["Volume"])


def subsurface_node(nodes, p):
    node = nodes.new("ShaderNodeSubsurfaceScattering")
    node.falloff = "RANDOM_WALK_FIXED_RADIUS"
    node.inputs["Color"].default_value = (*p["base-color"], 1.0)
    node.inputs["Scale"].default_value = 1.0
    node.inputs["Radius"].default_value = walk_radius(p)
    return node.outputs["BSSRDF"]


def principled_node(nodes, p):
    node = nodes["Principled BSDF"]
    node.distribution = "GGX"
    node.subsurface_method = "RANDOM_WALK_FIXED_RADIUS"
    f0 = p["specular"] * ((p["ior"] - 1) / (p["ior"] + 1)) ** 2
    values = {"Base Color": (*p["base-color"], 1.0), "Metallic": p["metallic"],
              "Roughness": p["roughness"], "Specular": f0 / 0.08, "IOR": p["ior"],
              "Transmission": p["transmission"], "Subsurface": p["subsurface"]}
    if p["subsurface"] > 0:
        values["Subsurface Color"] = (*p["base-color"], 1.0)
        values["Subsurface Radius"] = walk_radius(p)
    for key, value in values.items():
        node.inputs[key].default_value = value
    return node.outputs["BSDF"]


def principled_material(name, m):
    p = dict(KILN_DEFAULTS, **m["principled"])
    unknown = set(p) - SUPPORTED
    if unknown or p["subsurface"] not in (0, 1):
        raise ValueError("%s: no Cycles mapping for %s" % (name, sorted(unknown) or "subsurface"))
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    mat.cycles.homogeneous_volume = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    output = nodes["Material Output"]
    shader = subsurface_node if m.get("cycles_shader") == "subsurface_node" else principled_node
    links.new(shader(nodes, p), output.inputs["Surface"])
    sigma_a = absorption(p)
    if sigma_a:
        add_absorption(nodes, links, sigma_a, output)
    return mat
