# Generates scenes/cornell.dae: a Y-up Cornell box with CGL extras (area light, emitter quad, mirror and
# glass spheres, a diffuse block), written by hand for kiln.
quads = {
 # name: (material, 4 corners, counter-clockwise seen from inside)
 "floor":    ("white", [(-1,0,-1),(-1,0,1),(1,0,1),(1,0,-1)]),
 "ceiling":  ("white", [(-1,2,-1),(1,2,-1),(1,2,1),(-1,2,1)]),
 "backWall": ("white", [(-1,0,-1),(1,0,-1),(1,2,-1),(-1,2,-1)]),
 "leftWall": ("red",   [(-1,0,-1),(-1,2,-1),(-1,2,1),(-1,0,1)]),
 "rightWall":("green", [(1,0,-1),(1,0,1),(1,2,1),(1,2,-1)]),
 "emitter":  ("light", [(-0.25,1.999,-0.25),(0.25,1.999,-0.25),(0.25,1.999,0.25),(-0.25,1.999,0.25)]),
}
# a box (tall block) rotated 20 degrees
import math
def block(cx, cz, w, h, ang):
    c, s = math.cos(ang), math.sin(ang)
    def p(x, y, z):
        return (round(cx + c*x - s*z, 5), round(y, 5), round(cz + s*x + c*z, 5))
    hw = w/2
    v = [p(-hw,0,-hw),p(hw,0,-hw),p(hw,0,hw),p(-hw,0,hw),p(-hw,h,-hw),p(hw,h,-hw),p(hw,h,hw),p(-hw,h,hw)]
    faces = [tuple(reversed(f)) for f in [(0,3,2,1),(4,5,6,7),(0,1,5,4),(1,2,6,5),(2,3,7,6),(3,0,4,7)]]
    return v, faces
colors = {"white":(0.73,0.73,0.73),"red":(0.63,0.065,0.05),"green":(0.14,0.45,0.091),"light":(0.78,0.78,0.78)}
out = []
w = out.append
w('<?xml version="1.0" encoding="utf-8"?>')
w('<!-- kiln test scene: Cornell box with an area light, a mirror sphere, a glass sphere and a block. -->')
w('<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">')
w('  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>')
w('  <library_lights>')
w('    <light id="area-light" name="area"><technique_common><point><color>8 8 8</color><constant_attenuation>1</constant_attenuation><linear_attenuation>0</linear_attenuation><quadratic_attenuation>0</quadratic_attenuation></point></technique_common>')
w('      <extra><technique profile="CGL"><area><color>8 8 8</color></area></technique></extra></light>')
w('  </library_lights>')
w('  <library_cameras><camera id="cam" name="cam"><optics><technique_common><perspective><xfov>40</xfov><aspect_ratio>1.333333</aspect_ratio><znear>0.01</znear><zfar>100</zfar></perspective></technique_common></optics></camera></library_cameras>')
w('  <library_effects>')
for name,(r,g,b) in colors.items():
    extra = '<extra><technique profile="CGL"><emission><radiance>8 8 8</radiance></emission></technique></extra>' if name=="light" else ''
    w(f'    <effect id="{name}-effect"><profile_COMMON><technique sid="common"><lambert><diffuse><color>{r} {g} {b} 1</color></diffuse></lambert></technique></profile_COMMON>{extra}</effect>')
w('    <effect id="mirror-effect"><profile_COMMON><technique sid="common"><lambert><diffuse><color>0.8 0.8 0.8 1</color></diffuse></lambert></technique></profile_COMMON><extra><technique profile="CGL"><mirror><reflectance>0.95 0.95 0.95</reflectance></mirror></technique></extra></effect>')
w('    <effect id="glass-effect"><profile_COMMON><technique sid="common"><lambert><diffuse><color>0.8 0.8 0.8 1</color></diffuse></lambert></technique></profile_COMMON><extra><technique profile="CGL"><glass><reflectance>1 1 1</reflectance><transmittance>1 1 1</transmittance><roughness>0</roughness><ior>1.5</ior></glass></technique></extra></effect>')
w('  </library_effects>')
w('  <library_materials>')
for name in list(colors)+["mirror","glass"]:
    w(f'    <material id="{name}-material" name="{name}"><instance_effect url="#{name}-effect"/></material>')
w('  </library_materials>')
w('  <library_geometries>')
def geom(gid, verts, faces, mat):
    pos = " ".join(f"{x} {y} {z}" for (x,y,z) in verts)
    vc = " ".join(str(len(f)) for f in faces)
    p = " ".join(str(i) for f in faces for i in f)
    w(f'    <geometry id="{gid}" name="{gid}"><mesh>')
    w(f'      <source id="{gid}-pos"><float_array id="{gid}-pos-array" count="{3*len(verts)}">{pos}</float_array><technique_common><accessor source="#{gid}-pos-array" count="{len(verts)}" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>')
    w(f'      <vertices id="{gid}-vtx"><input semantic="POSITION" source="#{gid}-pos"/></vertices>')
    w(f'      <polylist material="{mat}-material" count="{len(faces)}"><input semantic="VERTEX" source="#{gid}-vtx" offset="0"/><vcount>{vc}</vcount><p>{p}</p></polylist>')
    w('    </mesh></geometry>')
for name,(mat,corners) in quads.items():
    geom(name, corners, [(0,1,2,3)], mat)
v,f = block(-0.35, -0.3, 0.55, 1.1, math.radians(20))
geom("block", v, f, "white")
for sid in ("sphereMirror","sphereGlass"):
    w(f'    <geometry id="{sid}" name="{sid}"><extra><technique profile="CGL"><sphere><radius>0.3</radius></sphere></technique></extra></geometry>')
w('  </library_geometries>')
w('  <library_visual_scenes><visual_scene id="Scene" name="Scene">')
ident = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"
w(f'    <node id="light" name="light"><matrix>0.5 0 0 0 0 0 1 1.998 0 -0.5 0 0 0 0 0 1</matrix><instance_light url="#area-light"/></node>')
w(f'    <node id="camera" name="camera"><matrix>1 0 0 0 0 1 0 1 0 0 1 4.6 0 0 0 1</matrix><instance_camera url="#cam"/></node>')
for name,(mat,_) in list(quads.items())+[("block",("white",None))]:
    w(f'    <node id="{name}-node" name="{name}"><matrix>{ident}</matrix><instance_geometry url="#{name}"><bind_material><technique_common><instance_material symbol="{mat}-material" target="#{mat}-material"/></technique_common></bind_material></instance_geometry></node>')
w(f'    <node id="mirror-node" name="mirror"><matrix>1 0 0 -0.45 0 1 0 0.3 0 0 1 0.45 0 0 0 1</matrix><instance_geometry url="#sphereMirror"><bind_material><technique_common><instance_material symbol="mirror-material" target="#mirror-material"/></technique_common></bind_material></instance_geometry></node>')
w(f'    <node id="glass-node" name="glass"><matrix>1 0 0 0.35 0 1 0 0.3 0 0 1 -0.35 0 0 0 1</matrix><instance_geometry url="#sphereGlass"><bind_material><technique_common><instance_material symbol="glass-material" target="#glass-material"/></technique_common></bind_material></instance_geometry></node>')
w('  </visual_scene></library_visual_scenes>')
w('  <scene><instance_visual_scene url="#Scene"/></scene>')
w('</COLLADA>')
import os; open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "cornell.dae"),"w").write("\n".join(out)+"\n")
