"""A two-bone skinned body for test_godot.py: the scene bend.tscn and, from the same numbers, the
closed form of where Godot 3.2 skins its vertices.

A square tube (its mesh in the MeshInstance's space) stands on bone "lower"; bone "upper" (a
child, its rest turned about X) bends about its own Z at BEND_DEG_PER_S (turn_bone.gd). The
MeshInstance is a child of the Skeleton, scaled and moved; the Skeleton's parent is turned and
moved. Its Skin has two binds in the other order than the bones: bind 0 names "upper", bind 1 is
bone index 0; vertices below LOW are all "lower", above HIGH all "upper", blended between.
The closed form (Godot's): world = MeshInstance global x sum_j w_j (bone global pose x bind
pose) x rest vertex, the bone global pose rest_lower (x rest_upper x pose_upper).

Transforms here are (basis rows, origin) pairs, as Godot's Transform literal lists them.
"""
import math

BEND_DEG_PER_S = 60.0
LOW, HIGH = 0.6, 0.8
HALF = 0.1                                        # the tube's half width
RINGS = [0.2 + 0.1 * k for k in range(11)]        # its rings' heights (mesh space)


def mul(a, b):
    (A, o), (B, p) = a, b
    C = [[sum(A[r][k] * B[k][c] for k in range(3)) for c in range(3)] for r in range(3)]
    return C, [sum(A[r][k] * p[k] for k in range(3)) + o[r] for r in range(3)]


def apply(a, v):
    A, o = a
    return [sum(A[r][k] * v[k] for k in range(3)) + o[r] for r in range(3)]


def inverse(a):
    A, o = a
    m = A
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    inv = [[(m[(c + 1) % 3][(r + 1) % 3] * m[(c + 2) % 3][(r + 2) % 3]
             - m[(c + 1) % 3][(r + 2) % 3] * m[(c + 2) % 3][(r + 1) % 3]) / det for c in range(3)] for r in range(3)]
    return inv, [-sum(inv[r][k] * o[k] for k in range(3)) for r in range(3)]


def rotation(axis, deg, origin=(0, 0, 0), scale=1.0):
    x, y, z = axis
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    R = [[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
         [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
         [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]]
    return [[scale * e for e in row] for row in R], list(origin)


def literal(a):
    A, o = a
    return "Transform( %s )" % ", ".join("%.9g" % x for x in [e for row in A for e in row] + list(o))


RIG = rotation((0, 1, 0), 30, (0.2, 0, -0.1))
REST_LOWER = rotation((1, 0, 0), 0, (0, 0.2, 0))
REST_UPPER = rotation((1, 0, 0), 15, (0, 0.5, 0))
MESH = rotation((0, 1, 0), 0, (0.05, 0, 0), scale=1.2)
BIND_UPPER = inverse(mul(REST_LOWER, REST_UPPER))   # bind 0
BIND_LOWER = inverse(REST_LOWER)                    # bind 1


def tube():
    """Vertices, triangles (clockwise seen from outside, Godot's front faces) and, per vertex,
    the weight of "upper" (bind 0; "lower", bind 1, has the rest)."""
    corners = [(HALF, HALF), (HALF, -HALF), (-HALF, -HALF), (-HALF, HALF)]   # clockwise from above
    verts = [(x, y, z) for y in RINGS for x, z in corners]
    tris = []
    for r in range(len(RINGS) - 1):
        for k in range(4):
            a, b = 4 * r + k, 4 * r + (k + 1) % 4
            tris += [a, b + 4, b, a, a + 4, b + 4]
    upper = [min(1.0, max(0.0, (v[1] - LOW) / (HIGH - LOW))) for v in verts]
    return verts, tris, upper


def scene():
    verts, tris, upper = tube()
    v3 = ", ".join("%.9g, %.9g, %.9g" % v for v in verts)
    bones = ", ".join(["0, 1, 0, 0"] * len(verts))
    weights = ", ".join("%.9g, %.9g, 0, 0" % (w, 1.0 - w) for w in upper)
    bone = '''bones/{i}/name = "{name}"
bones/{i}/parent = {parent}
bones/{i}/rest = {rest}
bones/{i}/enabled = true
bones/{i}/bound_children = [  ]
'''
    return f"""[gd_scene load_steps=6 format=2]

[ext_resource path="res://weft_cloth.gdns" type="Script" id=1]
[ext_resource path="res://turn_bone.gd" type="Script" id=2]

[sub_resource type="ArrayMesh" id=1]
surfaces/0 = {{
"primitive": 4,
"arrays": [ PoolVector3Array( {v3} ), null, null, null, null, null, PoolIntArray( {bones} ), PoolRealArray( {weights} ), PoolIntArray( {", ".join(map(str, tris))} ) ],
"morph_arrays": [  ]
}}

[sub_resource type="Skin" id=2]
bind_count = 2
bind/0/name = "upper"
bind/0/bone = -1
bind/0/pose = {literal(BIND_UPPER)}
bind/1/bone = 0
bind/1/pose = {literal(BIND_LOWER)}

[sub_resource type="PlaneMesh" id=3]
size = Vector2( 0.6, 0.6 )
subdivide_width = 5
subdivide_depth = 5

[node name="Main" type="Spatial"]

[node name="Rig" type="Spatial" parent="."]
transform = {literal(RIG)}

[node name="Skeleton" type="Skeleton" parent="Rig"]
{bone.format(i=0, name="lower", parent=-1, rest=literal(REST_LOWER))}{bone.format(i=1, name="upper", parent=0, rest=literal(REST_UPPER))}script = ExtResource( 2 )
bone = "upper"
axis = Vector3( 0, 0, 1 )
degrees_per_second = {BEND_DEG_PER_S}

[node name="BodyMesh" type="MeshInstance" parent="Rig/Skeleton"]
transform = {literal(MESH)}
mesh = SubResource( 1 )
skin = SubResource( 2 )
skeleton = NodePath("..")

[node name="Cloth" type="MeshInstance" parent="."]
transform = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.2, 1.9, -0.1 )
mesh = SubResource( 3 )
script = ExtResource( 1 )
body = NodePath("../Rig/Skeleton/BodyMesh")
"""


def skinned(seconds):
    """The tube's world vertices with "upper" bent by BEND_DEG_PER_S x seconds."""
    verts, _, upper = tube()
    lower = mul(REST_LOWER, BIND_LOWER)
    bent = mul(mul(mul(REST_LOWER, REST_UPPER), rotation((0, 0, 1), BEND_DEG_PER_S * seconds)), BIND_UPPER)
    node = mul(RIG, MESH)
    out = []
    for v, w in zip(verts, upper):
        a, b = apply(lower, v), apply(bent, v)
        out.append(apply(node, [(1 - w) * a[k] + w * b[k] for k in range(3)]))
    return out
