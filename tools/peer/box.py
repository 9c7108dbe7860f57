"""The quads of the peer benchmark's scenes (the closed box, the uplit room, a floor): kiln reads them
from a generated COLLADA file and Cycles builds them from the same corner list
(tools/peer/cycles_scene.py).

The box is closed on all six sides (the camera sits inside it), so no light leaves it except through
the back of the emitter: the emitting quad fills a hole in the ceiling, flush with it, and faces down.
Both renderers emit from both sides of a mesh light; the back side looks out of the box into black, so
the sidedness cannot make the two differ.
"""

WHITE, RED, GREEN = [0.73, 0.73, 0.73], [0.63, 0.065, 0.05], [0.14, 0.45, 0.091]


def quad(x0, x1, y0, y1, z0, z1, axis):
    """The rectangle spanning [x0,x1] x [y0,y1] x [z0,z1] with `axis` the flat one."""
    if axis == "y":
        return [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)]
    if axis == "x":
        return [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)]
    return [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)]


def box_quads(lo, hi, light_half, radiance):
    """(name, material, corners): material is {"albedo": rgb} or {"emission": rgb} (radiance)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    cx, cz, h = (x0 + x1) / 2, (z0 + z1) / 2, light_half
    lx0, lx1, lz0, lz1 = cx - h, cx + h, cz - h, cz + h
    white, emit = {"albedo": WHITE}, {"emission": radiance}
    return [
        ("floor", white, quad(x0, x1, y0, y0, z0, z1, "y")),
        ("back", white, quad(x0, x1, y0, y1, z0, z0, "z")),
        ("front", white, quad(x0, x1, y0, y1, z1, z1, "z")),
        ("left", {"albedo": RED}, quad(x0, x0, y0, y1, z0, z1, "x")),
        ("right", {"albedo": GREEN}, quad(x1, x1, y0, y1, z0, z1, "x")),
        # the ceiling around the light's hole, in four strips
        ("ceiling_back", white, quad(x0, x1, y1, y1, z0, lz0, "y")),
        ("ceiling_front", white, quad(x0, x1, y1, y1, lz1, z1, "y")),
        ("ceiling_left", white, quad(x0, lx0, y1, y1, lz0, lz1, "y")),
        ("ceiling_right", white, quad(lx1, x1, y1, y1, lz0, lz1, "y")),
        ("light", emit, quad(lx0, lx1, y1, y1, lz0, lz1, "y")),
    ]


def room_quads(lo, hi, pedestal_xz, half, height, radiance):
    """A closed room (white, red left wall, green right wall, no light in the ceiling) lit only by an
    uplighter: a pedestal whose top is an emitting quad facing the ceiling. The pedestal's sides and
    the floor close it, so the emitter's back side lights only its inside, which no camera path
    reaches (both renderers emit from both sides)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    white = {"albedo": WHITE}
    px, pz = pedestal_xz
    a0, a1, b0, b1 = px - half, px + half, pz - half, pz + half
    return [
        ("floor", white, quad(x0, x1, y0, y0, z0, z1, "y")),
        ("ceiling", white, quad(x0, x1, y1, y1, z0, z1, "y")),
        ("back", white, quad(x0, x1, y0, y1, z0, z0, "z")),
        ("front", white, quad(x0, x1, y0, y1, z1, z1, "z")),
        ("left", {"albedo": RED}, quad(x0, x0, y0, y1, z0, z1, "x")),
        ("right", {"albedo": GREEN}, quad(x1, x1, y0, y1, z0, z1, "x")),
        ("pedestal_back", white, quad(a0, a1, y0, y0 + height, b0, b0, "z")),
        ("pedestal_front", white, quad(a0, a1, y0, y0 + height, b1, b1, "z")),
        ("pedestal_left", white, quad(a0, a0, y0, y0 + height, b0, b1, "x")),
        ("pedestal_right", white, quad(a1, a1, y0, y0 + height, b0, b1, "x")),
        ("uplighter", {"emission": radiance}, quad(a0, a1, y0 + height, y0 + height, b0, b1, "y")),
    ]


def floor_quad(half, albedo):
    """A square floor at y = 0 (for meshes under an environment)."""
    return [("floor", {"albedo": albedo}, quad(-half, half, 0.0, 0.0, -half, half, "y"))]


def write_dae(path, quads):
    """A Y-up COLLADA file, one geometry per quad; emission as the CS184 scenes write it (a CGL
    <emission><radiance> extra: kiln makes it an Emission material of that radiance, sampled as a mesh
    light)."""
    out = ['<?xml version="1.0" encoding="utf-8"?>',
           '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">',
           '  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>',
           '  <library_effects>']
    for name, mat, _ in quads:
        rgb = mat.get("albedo", [0, 0, 0])
        emission = ""
        if "emission" in mat:
            emission = ('<extra><technique profile="CGL"><emission><radiance>%g %g %g</radiance>'
                        '</emission></technique></extra>' % tuple(mat["emission"]))
        out.append('    <effect id="%s-fx"><profile_COMMON><technique sid="common"><lambert>'
                   '<diffuse><color>%g %g %g 1</color></diffuse></lambert></technique>'
                   '</profile_COMMON>%s</effect>' % ((name,) + tuple(rgb) + (emission,)))
    out.append('  </library_effects>\n  <library_materials>')
    for name, _, _ in quads:
        out.append('    <material id="%s-mat" name="%s"><instance_effect url="#%s-fx"/></material>'
                   % (name, name, name))
    out.append('  </library_materials>\n  <library_geometries>')
    for name, _, corners in quads:
        pos = " ".join("%g %g %g" % c for c in corners)
        out.append(
            '    <geometry id="%s"><mesh><source id="%s-p"><float_array id="%s-a" count="12">%s'
            '</float_array><technique_common><accessor source="#%s-a" count="4" stride="3">'
            '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
            '</accessor></technique_common></source><vertices id="%s-v"><input semantic="POSITION" '
            'source="#%s-p"/></vertices><polylist material="m" count="1"><input semantic="VERTEX" '
            'source="#%s-v" offset="0"/><vcount>4</vcount><p>0 1 2 3</p></polylist></mesh></geometry>'
            % (name, name, name, pos, name, name, name, name))
    out.append('  </library_geometries>\n  <library_visual_scenes><visual_scene id="scene">')
    for name, _, _ in quads:
        out.append('    <node id="%s-node"><instance_geometry url="#%s"><bind_material><technique_common>'
                   '<instance_material symbol="m" target="#%s-mat"/></technique_common></bind_material>'
                   '</instance_geometry></node>' % (name, name, name))
    out.append('  </visual_scene></library_visual_scenes>\n'
               '  <scene><instance_visual_scene url="#scene"/></scene>\n</COLLADA>')
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
