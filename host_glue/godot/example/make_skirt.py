"""Writes skirt.tscn: a skirt (an open cone, SEGMENTS around x RINGS down, as an ArrayMesh in the
scene) attached at its waist ring to the bone "hips" of a Skeleton inside a turning body (a cone
widening from the waist to below the hem, 3 mm inside the skirt, within the collider's
thickness: the skirt rests on it from the start, and its friction turns the skirt). Run: python3 make_skirt.py > skirt.tscn"""
import math

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
v3 = ", ".join("%.6g, %.6g, %.6g" % v for v in verts)
print(f"""[gd_scene load_steps=5 format=2]

[ext_resource path="res://weft_cloth.gdns" type="Script" id=1]
[ext_resource path="res://turn.gd" type="Script" id=2]

[sub_resource type="ArrayMesh" id=1]
surfaces/0 = {{
"primitive": 4,
"arrays": [ PoolVector3Array( {v3} ), null, null, null, null, null, null, null, PoolIntArray( {", ".join(map(str, tris))} ) ],
"morph_arrays": [  ]
}}

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
bones/0/name = "hips"
bones/0/parent = -1
bones/0/rest = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0 )
bones/0/enabled = true
bones/0/bound_children = [  ]

[node name="BodyMesh" type="MeshInstance" parent="Body"]
transform = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.55, 0 )
mesh = SubResource( 2 )

[node name="Skirt" type="MeshInstance" parent="."]
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
body = NodePath("../Body/BodyMesh")
""", end="")
