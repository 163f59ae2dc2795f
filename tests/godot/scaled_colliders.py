"""Godot collision shapes under scaled transforms as `weft run` colliders, for test_godot.py,
computed here from each shape's sizes and its node's global transform (a column-major 4x4) the
way Godot scales a shape: a sphere's or capsule's sizes times the (uniform) scale, a plane mapped
by the transform (its normal by the basis inverse-transposed).

unscaled=True gives the collider with the scale ignored (sizes as given, the plane placed by the
transform's rotation alone): the plugin before it applied scales, which the test rules out.
"""
import math

UNIFORM = 1e-4   # axes whose lengths differ by no more than this fraction are a uniform scale


def _column(m, k):
    return m[4 * k:4 * k + 3]


def _norm(v):
    return math.sqrt(sum(x * x for x in v))


def _unit(v):
    n = _norm(v)
    return [x / n for x in v]


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _rotation(m):
    """The transform's rotation as the plugin took it before scales: Gram-Schmidt of X then Y."""
    x = _unit(_column(m, 0))
    y = _column(m, 1)
    y = _unit([y[k] - _dot(x, y) * x[k] for k in range(3)])
    return [x, y, _cross(x, y)]   # columns


def is_uniform(m):
    s = [_norm(_column(m, k)) for k in range(3)]
    return max(s) - min(s) <= UNIFORM * max(s)


def weft_collider(c, settings, unscaled=False):
    """A recorded collider (record.gd's _colliders) as a weft run collider; None for a sphere or
    capsule whose scale is not uniform (the plugin refuses them)."""
    m = c["transform"]
    origin = m[12:15]
    s = 1.0 if unscaled else sum(_norm(_column(m, k)) for k in range(3)) / 3
    out = {"thickness": settings["collider_thickness"], "friction": settings["collider_friction"]}
    if ("sphere" in c or "capsule" in c) and not unscaled and not is_uniform(m):
        return None
    if "sphere" in c:
        out.update({"type": "sphere", "center": origin, "radius": s * c["sphere"]})
    elif "capsule" in c:   # Godot's capsule: along local Z, height the cylinder's length
        radius, height = c["capsule"]
        axis = _unit(_column(m, 2))
        half = s * height / 2
        out.update({"type": "capsule", "radius": s * radius, "a": [origin[k] - half * axis[k] for k in range(3)],
                    "b": [origin[k] + half * axis[k] for k in range(3)]})
    else:
        n, d = c["plane"][:3], c["plane"][3]
        if unscaled:
            cols = _rotation(m)
        else:
            cols = [_column(m, k) for k in range(3)]
        basis = [[cols[col][row] for col in range(3)] for row in range(3)]
        point = [_dot(basis[r], n) * d + origin[r] for r in range(3)]
        if unscaled:
            normal = [_dot(basis[r], n) for r in range(3)]
        else:   # the inverse transpose: cofactors over the determinant
            cof = [[basis[(r + 1) % 3][(k + 1) % 3] * basis[(r + 2) % 3][(k + 2) % 3]
                    - basis[(r + 1) % 3][(k + 2) % 3] * basis[(r + 2) % 3][(k + 1) % 3] for k in range(3)]
                   for r in range(3)]
            det = _dot(basis[0], cof[0])
            normal = [_dot(cof[r], n) / det for r in range(3)]
        normal = _unit(normal)
        out.update({"type": "plane", "normal": normal, "offset": _dot(normal, point)})
    return out
