"""Writes skirt.tscn: a skirt (an open cone, SEGMENTS around x RINGS down, as an ArrayMesh in the
scene) attached at its waist ring to the bone "hips" of a Skeleton inside a turning body (a cone
widening from the waist to below the hem, 3 mm inside the skirt, within the collider's
thickness: the skirt rests on it from the start, and its friction turns the skirt). Run: python3 make_skirt.py > skirt.tscn

With --skinned it writes skinned_skirt.tscn: the same skirt and body, but the body does not
turn as a node: its mesh (the same cone, as an ArrayMesh whose every vertex is weighted to the
bone "hips") is skinned by a Skeleton whose bone turns (turn_bone.gd), as an imported character
is. Run: python3 make_skirt.py --skinned > skinned_skirt.tscn"""
import math
import sys

SKINNED = "--skinned" in sys.argv[1:]

SEGMENTS, RINGS = 24, 7
WAIST_R, WAIST_Y, HEM_R, HEM_Y = 0.13, 1.0, 0.3, 0.5

verts = []
for r in range(RINGS):
    s = r / (RINGS - 1)
    rad, y = WAIST_R + (HEM_R - WAIST_R) * s, WAIST_Y + (HEM_Y - WAIST_Y) * s
    for k in range(SEGMENTS):
        a = 2 * math.pi * k / SEGMENTS
        verts.append((rad * math.sin(a), y, rad * math.cos(a)))
tris = []   # clockwise seen from outside: Godot's front faces
for r in range(RINGS - 1):
    for k in range(SEGMENTS):
        a, b = r * SEGMENTS + k, r * SEGMENTS + (k + 1) % SEGMENTS
        c, d = a + SEGMENTS, b + SEGMENTS
        tris += [a, b, c, b, d, c]
def body_cone():
    """The body: the vertices and triangles Godot's CylinderMesh of skirt.tscn has (top radius
    0.11 at y = 0.5, bottom 0.45 at y = -0.5, 24 segments, one ring between, seam vertices
    doubled, closed by caps; CylinderMesh::_create_mesh_array), so that both bodies are the
    same mesh."""
    n, rings, top, bottom, height = 24, 1, 0.11, 0.45, 1.0
    v, t = [], []
    for j in range(rings + 2):
        s = j / (rings + 1)
        rad, y = top + (bottom - top) * s, height * 0.5 - height * s
        for i in range(n + 1):
            a = 2 * math.pi * i / n
            v.append((math.sin(a) * rad, y, math.cos(a) * rad))
            if i > 0 and j > 0:
                prev, this = (j - 1) * (n + 1), j * (n + 1)
                t += [prev + i - 1, prev + i, this + i - 1, prev + i, this + i, this + i - 1]
    for y, rad, flip in ((height * 0.5, top, False), (-height * 0.5, bottom, True)):
        centre = len(v)
        v.append((0.0, y, 0.0))
        for i in range(n + 1):
            a = 2 * math.pi * i / n
            v.append((math.sin(a) * rad, y, math.cos(a) * rad))
            if i > 0:
                p = len(v)
                t += [centre, p - 2, p - 1] if flip else [centre, p - 1, p - 2]
    return v, t


def vec3(vs):
    return ", ".join("%.6g, %.6g, %.6g" % v for v in vs)


v3 = vec3(verts)
skirt_mesh = f"""[sub_resource type="ArrayMesh" id=1]
surfaces/0 = {{
"primitive": 4,
"arrays": [ PoolVector3Array( {v3} ), null, null, null, null, null, null, null, PoolIntArray( {", ".join(map(str, tris))} ) ],
"morph_arrays": [  ]
}}
"""
skeleton = """bones/0/name = "hips"
bones/0/parent = -1
bones/0/rest = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0 )
bones/0/enabled = true
bones/0/bound_children = [  ]
"""
skirt = f"""[node name="Skirt" type="MeshInstance" parent="."]
mesh = SubResource( 1 )
script = ExtResource( 1 )
density = 0.12
stiffness_stretch = 3000.0
stiffness_shear = 100.0
stiffness_bend = 1.0
substeps = 2
collider_friction = 0.1
attach_skeleton = NodePath("../Body/Skeleton")
attach_bones = PoolStringArray( "hips" )
attach_vertices = [ PoolIntArray( {", ".join(map(str, range(SEGMENTS)))} ) ]
"""
if not SKINNED:
    print(f"""[gd_scene load_steps=5 format=2]

[ext_resource path="res://weft_cloth.gdns" type="Script" id=1]
[ext_resource path="res://turn.gd" type="Script" id=2]

{skirt_mesh}
[sub_resource type="CylinderMesh" id=2]
top_radius = 0.11
bottom_radius = 0.45
height = 1.0
radial_segments = 24
rings = 1

[node name="Main" type="Spatial"]

[node name="Body" type="Spatial" parent="."]
script = ExtResource( 2 )

[node name="Skeleton" type="Skeleton" parent="Body"]
{skeleton}
[node name="BodyMesh" type="MeshInstance" parent="Body"]
transform = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.55, 0 )
mesh = SubResource( 2 )

{skirt}body = NodePath("../Body/BodyMesh")
""", end="")
else:
    bv, bt = body_cone()
    print(f"""[gd_scene load_steps=5 format=2]

[ext_resource path="res://weft_cloth.gdns" type="Script" id=1]
[ext_resource path="res://turn_bone.gd" type="Script" id=2]

{skirt_mesh}
[sub_resource type="ArrayMesh" id=2]
surfaces/0 = {{
"primitive": 4,
"arrays": [ PoolVector3Array( {vec3(bv)} ), null, null, null, null, null, PoolIntArray( {", ".join(["0, 0, 0, 0"] * len(bv))} ), PoolRealArray( {", ".join(["1, 0, 0, 0"] * len(bv))} ), PoolIntArray( {", ".join(map(str, bt))} ) ],
"morph_arrays": [  ]
}}

[node name="Main" type="Spatial"]

[node name="Body" type="Spatial" parent="."]

[node name="Skeleton" type="Skeleton" parent="Body"]
{skeleton}script = ExtResource( 2 )

[node name="BodyMesh" type="MeshInstance" parent="Body/Skeleton"]
transform = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.55, 0 )
mesh = SubResource( 2 )

{skirt}body = NodePath("../Body/Skeleton/BodyMesh")
""", end="")
