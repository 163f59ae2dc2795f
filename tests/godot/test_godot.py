"""WeftCloth in a headless Godot (godot3-server) against `weft run` of the same scene.

    test_godot.py GODOT_SERVER LIBWEFT_GODOT WEFT_CLI PROJECT_DIR RECORD_GD

1. The example project (host_glue/godot/example) is copied to a scratch folder with its .gdnlib
   pointing at the built library, and flag.tscn runs for FRAMES physics frames (record.gd). The
   flag's mesh, settings, ball and final vertices (read back from the node's ArrayMesh) come
   back as JSON.
2. The same scene as a `weft run` scene file: the Godot mesh as an OBJ (triangles wound
   counter-clockwise, as the plugin hands them to Weft; vertices written in first-use order, so
   that the file's order and assimp's are the same), the node's transform, the pins, the ball
   and the ground plane, the same material and solver settings, 60 fps. The same for skirt.tscn
   (the waist's bone attachment as pins and the body as a mesh collider, both spinning as the
   body does; limit MAX_DIFF_SKIRT, and the body must matter: weft run without it, or with it
   not turning, must be BODY_MATTERS away) and for skinned_skirt.tscn (its body is skinned to a
   turning bone; for weft run it is the rigid spinning body of skirt.tscn). Its last frame must
   match Godot's: largest distance below MAX_DIFF m (both run the same library on the same
   input; what differs is rounding on the way: Godot's JSON and the OBJ text), while the flag
   has moved more than MIN_MOTION m (the comparison is not of two resting meshes).
   A two-surface flag against weft run of its surfaces joined (the plugin's vertex order: the
   flag's last frame moves by about 2 cm with the order of its vertices alone, weft run of the
   flag against weft run of its OBJ with the vertex order reversed: contact with the ball makes
   it sensitive to the solver's rounding), its seam welded, its materials kept.
   bend.tscn (bend_scene.py): a two-bone skinned body, bent over the run; the world vertices the
   plugin skinned (get_body_vertices) must be bend_scene's closed form within MAX_DIFF_SKIN.
3. Broken settings: a NaN property, a mesh path that does not exist and a colliders_root that
   names no node give Godot errors naming each, the process exits 0 (no crash), the NaN is not
   taken and the node without a mesh does not simulate; so do bad attachments and bodies
   (skinned ones with a bad skin included: those nodes simulate without the body) and a mesh
   with a surface of lines (not simulated).
Exit 77 (skipped) when godot3-server is missing.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import bend_scene
import scaled_colliders

FRAMES = 40
MAX_DIFF = 5e-4
# The flag (176 particles) leans on the ball. Since 0.9.2 it runs at the CPU's small-cloth default,
# block IC(0) with every Newton solve to the tolerance (docs/bench/precond_by_size.md), which leaves
# more of the tolerance's error in the soft modes than the multigrid: a change of the ball's radius
# by a relative 1e-7 (float rounding's size) moves weft run's own last frame by 0.53 mm (3.7e-7 m
# on the multigrid), and Godot (float inputs) lay 3.9 mm from weft run. So the flag is held to
# 5 mm, as the skirt and the scaled colliders are below.
MAX_DIFF_FLAG = 5e-3
# The skirt rests on its turning body with friction: a change of its spin rate by a relative 1e-6
# (float rounding's size) moves weft run's own last frame by 3.7 mm, so Godot (float transforms)
# and weft run (double motions) are held to 5 mm; without the body, or with a body that does not
# turn, weft run's skirt lies 15 to 17 mm from Godot's, so the body must matter by more than
# BODY_MATTERS m. The same holds for the scaled colliders: each scale must matter by as much.
MAX_DIFF_SKIRT = 5e-3
# The flag on scaled colliders leans on the ball: a change of the ball's radius by a relative 1e-7
# (float rounding's size; Godot's shapes and transforms are floats) moves weft run's own last frame
# by 2.3-2.5 mm, with the multigrid's float V-cycle or its double one, so Godot is held to 5 mm
# there; each collider's scale must still matter by BODY_MATTERS.
MAX_DIFF_SCALED = 5e-3
BODY_MATTERS = 1e-2
MIN_MOTION = 0.2
# bend.tscn's skinned body against the closed form: float arithmetic and Godot's 16-bit weights
# (a 1/65535 error over a 1 m arm) are far below it
MAX_DIFF_SKIN = 1e-4


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def run_godot(server, project, mode, out, tmp):
    env = dict(os.environ, WEFT_GODOT_MODE=mode, WEFT_GODOT_OUT=out, WEFT_GODOT_FRAMES=str(FRAMES),
               LANG="C.UTF-8", HOME=tmp, XDG_DATA_HOME=tmp, XDG_CONFIG_HOME=tmp, XDG_CACHE_HOME=tmp)
    p = subprocess.run([server, "--path", project, "-s", "res://record.gd"], env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    print(f"--- godot3-server ({mode}) exit {p.returncode}\n{p.stdout}")
    if p.returncode != 0:
        fail(f"godot3-server exited {p.returncode} in mode {mode}")
    if "SCRIPT ERROR" in p.stdout:
        fail(f"record.gd failed in mode {mode}")
    if not os.path.exists(out):
        fail(f"record.gd wrote no {out} in mode {mode}")
    with open(out) as f:
        return json.load(f), p.stdout


def transform_point(m, p):
    return [m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] for r in range(3)]


def write_obj(rest_flat, idx, path, keep_order=False):
    """A Godot surface as an OBJ, triangles wound counter-clockwise, vertices in first-use order
    (or in Godot's order: keep_order). Returns that order (OBJ vertex k is Godot vertex order[k])
    and its inverse."""
    rest = [rest_flat[3 * i:3 * i + 3] for i in range(len(rest_flat) // 3)]
    tris = [(idx[t], idx[t + 2], idx[t + 1]) for t in range(0, len(idx), 3)]   # counter-clockwise
    order = []
    new_of = {}
    for v in (range(len(rest)) if keep_order else (v for t in tris for v in t)):
        if v not in new_of:
            new_of[v] = len(order)
            order.append(v)
    if keep_order and len({v for t in tris for v in t}) != len(rest):
        fail("the Godot mesh has vertices no triangle uses")
    if len(order) != len(rest):
        fail("the Godot mesh has vertices no triangle uses")
    with open(path, "w") as f:
        for v in order:
            f.write("v %.9g %.9g %.9g\n" % tuple(rest[v]))
        for t in tris:
            f.write("f %d %d %d\n" % tuple(new_of[v] + 1 for v in t))
    return order, new_of


def settings_scene(g, name):
    """The parts of a weft run scene every Godot scene shares: mesh, transform, settings, time."""
    s = g["settings"]
    return {
        "description": f"host_glue/godot/example/{name}.tscn as a weft run scene (test_godot.py)",
        "mesh": {"file": f"{name}.obj"},
        "transform": g["transform"],
        "material": {"density": s["density"],
                     "k": {"stretch": s["stiffness_stretch"], "shear": s["stiffness_shear"],
                           "bend": s["stiffness_bend"]},
                     "d": {"stretch": s["damping_stretch"], "shear": s["damping_shear"],
                           "bend": s["damping_bend"]}},
        # the node's tolerance -1 (weft_default_cloth_def's) is the library's choice: "default" in a scene
        "solver": {"type": "pcg", "tolerance": s["tolerance"] if s["tolerance"] >= 0 else "default",
                   "max_iterations": s["max_iterations"]},
        "time": {"fps": round(1.0 / g["dt"]), "substeps": s["substeps"], "frames": g["frames"]},
    }


def skirt_scene(g, tmp, name="skirt"):
    """skirt.tscn: the waist on the bone as pins spinning with the body, the body (its Godot mesh
    as an OBJ) as a mesh collider with the same spin. skinned_skirt.tscn is the same scene for
    weft run: there the body turns because its one bone does (all its weights are on it)."""
    order, new_of = write_obj(g["rest"], g["indices"], os.path.join(tmp, name + ".obj"))
    b = g["body"]
    write_obj(b["rest"], b["indices"], os.path.join(tmp, name + "_body.obj"))
    s = g["settings"]
    spin = {"pivot": [0, 0, 0], "spin_axis": [0, 1, 0], "spin_deg_per_s": b["degrees_per_second"]}
    scene = settings_scene(g, name)
    scene["pins"] = [{"vertices": [new_of[v] for v in g["attached"]], "motion": spin}]
    scene["colliders"] = [{"type": "mesh", "file": name + "_body.obj", "transform": b["transform"], "motion": spin,
                           "thickness": s["collider_thickness"], "friction": s["collider_friction"]}]
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, order


def scaled_scene(g, tmp):
    """The flag with scaled colliders: as flag, its colliders as scaled_colliders makes them."""
    order, new_of = write_obj(g["rest"], g["indices"], os.path.join(tmp, "scaled.obj"))
    scene = settings_scene(g, "scaled")
    scene["pins"] = [{"vertices": [new_of[v] for v in g["pinned"]]}]
    scene["colliders"] = [c for c in (scaled_colliders.weft_collider(c, g["settings"]) for c in g["colliders"]) if c]
    path = os.path.join(tmp, "scaled.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, order


def weft_scene(g, tmp, name="flag", keep_order=False):
    order, new_of = write_obj(g["rest"], g["indices"], os.path.join(tmp, name + ".obj"), keep_order)
    s = g["settings"]
    scene = settings_scene(g, name)
    scene.update({
        "pins": [{"vertices": [new_of[v] for v in g["pinned"]]}],
        "colliders": [
            {"type": "sphere", "center": g["ball"]["center"], "radius": g["ball"]["radius"],
             "thickness": s["collider_thickness"], "friction": s["collider_friction"]},
            {"type": "plane", "normal": [0, 1, 0], "offset": 0,
             "thickness": s["collider_thickness"], "friction": s["collider_friction"]}]})
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, order


def read_obj(path):
    with open(path) as f:
        return [[float(x) for x in line.split()[1:4]] for line in f if line.startswith("v ")]


def run_variant(weft_cli, scene, out):
    """weft run of a scene dict (written next to out); its last frame."""
    with open(out + ".json", "w") as f:
        json.dump(scene, f)
    q = subprocess.run([weft_cli, "run", out + ".json", "--out", out, "--quiet", "--threads", "1"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    if q.returncode != 0:
        fail(f"weft run of {out}.json failed: {q.stdout}")
    return read_obj(os.path.join(out, "frame_%04d.obj" % FRAMES))


def body_variants(g, base):
    """The skirt's scene without its body, and with a body that does not turn."""
    still = json.loads(json.dumps(base))
    del still["colliders"][0]["motion"]
    return {"without the body": dict(base, colliders=[]), "with a body that does not turn": still}


def scaled_variants(g, base):
    """The scaled flag's scene with each scaled collider unscaled in turn, and with the refused
    (non-uniformly scaled) sphere taken as a sphere of its radius times its smallest scale."""
    out = {}
    kept = [c for c in g["colliders"] if scaled_colliders.weft_collider(c, g["settings"])]
    for i, c in enumerate(kept):
        other = json.loads(json.dumps(base))
        other["colliders"][i] = scaled_colliders.weft_collider(c, g["settings"], unscaled=True)
        out[f"with {c['name']} unscaled"] = other
    for c in g["colliders"]:
        if c not in kept:
            m = c["transform"]
            small = min(math.dist(m[4 * k:4 * k + 3], [0, 0, 0]) for k in range(3))
            sphere = scaled_colliders.weft_collider(c, g["settings"], unscaled=True)   # unscaled: never refused
            sphere["radius"] *= small
            out[f"with {c['name']} as a sphere of radius {sphere['radius']:.3g}"] = dict(
                base, colliders=base["colliders"] + [sphere])
    return out


def compare(server, project, weft_cli, tmp, mode, make_scene, limit, variants_of=lambda g, base: {}):
    """Godot's mode against weft run of make_scene's scene within limit; and each scene
    variants_of gives (what the plugin must not be doing) at least BODY_MATTERS away."""
    g, log = run_godot(server, project, mode, os.path.join(tmp, mode + "_out.json"), tmp)
    if not g["simulating"] or g["frames"] != FRAMES:
        fail(f"the {mode} did not simulate {FRAMES} frames: {g['simulating']}, {g['frames']}")
    scene, order = make_scene(g, tmp)
    out = os.path.join(tmp, "weft_run_" + mode)
    p = subprocess.run([weft_cli, "run", scene, "--out", out, "--quiet", "--threads", "1"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    print(f"--- weft run exit {p.returncode}\n{p.stdout}")
    if p.returncode != 0:
        fail("weft run failed")
    ref = read_obj(os.path.join(out, "frame_%04d.obj" % FRAMES))
    with open(scene) as f:
        base = json.load(f)
    variants = {what: run_variant(weft_cli, other, f"{out}_{k}")
                for k, (what, other) in enumerate(variants_of(g, base).items())}
    m = g["transform"]
    n = len(order)
    godot_world = [transform_point(m, g["positions"][3 * i:3 * i + 3]) for i in range(n)]
    rest_world = [transform_point(m, g["rest"][3 * i:3 * i + 3]) for i in range(n)]
    diff = max(math.dist(godot_world[v], ref[k]) for k, v in enumerate(order))
    motion = max(math.dist(godot_world[i], rest_world[i]) for i in range(n))
    if any(not math.isfinite(x) for p in godot_world for x in p):
        fail("non-finite positions from Godot")
    print(f"{mode}, frame {FRAMES}: largest Godot - weft run distance {diff:.3g} m (limit {limit}), "
          f"largest motion from rest {motion:.3g} m (at least {MIN_MOTION})")
    for what, other in variants.items():
        d = max(math.dist(godot_world[v], other[k]) for k, v in enumerate(order))
        print(f"{mode}: largest distance from weft run {what} {d:.3g} m (at least {BODY_MATTERS})")
        if d < BODY_MATTERS:
            fail(f"{mode}: Godot's result is that of weft run {what}")
    if diff > limit:
        fail(f"Godot's {mode} differs from weft run's")
    if motion < MIN_MOTION:
        fail(f"the {mode} barely moved")
    return log


def check_surfaces(server, project, weft_cli, tmp):
    """The flag's mesh split into two surfaces (record.gd): weft run of the surfaces joined as
    the plugin documents it (surface 1's vertices after surface 0's) against each surface's
    vertices as the plugin wrote them back; the seam's two copies of a vertex must stay together
    (Weft welds them) and each surface keeps its material."""
    g, _ = run_godot(server, project, "surfaces", os.path.join(tmp, "surfaces_out.json"), tmp)
    if not g["simulating"] or g["frames"] != FRAMES:
        fail(f"the two-surface flag did not simulate {FRAMES} frames: {g['simulating']}, {g['frames']}")
    rest, indices, positions = [], [], []
    for surface in g["surfaces"]:
        indices += [len(rest) // 3 + i for i in surface["indices"]]
        rest += surface["rest"]
        positions += surface["positions"]
    joined = dict(g, rest=rest, indices=indices, pinned=g["joined_pinned"])
    scene, order = weft_scene(joined, tmp, "surfaces", keep_order=True)
    ref = run_variant(weft_cli, json.load(open(scene)), os.path.join(tmp, "weft_run_surfaces"))
    m = g["transform"]
    world = [transform_point(m, positions[3 * i:3 * i + 3]) for i in range(len(positions) // 3)]
    diff = max(math.dist(world[v], ref[k]) for k, v in enumerate(order))
    twins = {}
    for i in range(len(world)):
        twins.setdefault(tuple(rest[3 * i:3 * i + 3]), []).append(world[i])
    seam = [w for w in twins.values() if len(w) > 1]
    apart = max(math.dist(w[0], w[1]) for w in seam) if seam else math.inf
    materials = [surface["material"] for surface in g["surfaces"]]
    print(f"surfaces: {len(g['surfaces'])} surfaces, materials {materials}; largest distance from weft run of them "
          f"joined {diff:.3g} m (limit {MAX_DIFF}); {len(seam)} seam vertices, their copies at most {apart:.3g} m "
          f"apart (limit {MAX_DIFF})")
    if materials != ["left", "right"]:
        fail("the two-surface flag lost a surface or its material")
    if diff > MAX_DIFF:
        fail("the two-surface flag differs from weft run of its surfaces joined")
    if not seam or apart > MAX_DIFF:
        fail("the two-surface flag's seam came apart")


def check_bend(server, project, tmp):
    """bend.tscn: the body vertices the plugin skinned against bend_scene's closed form."""
    with open(os.path.join(project, "bend.tscn"), "w") as f:
        f.write(bend_scene.scene())
    g, _ = run_godot(server, project, "bend", os.path.join(tmp, "bend_out.json"), tmp)
    if not g["simulating"] or g["frames"] != FRAMES:
        fail(f"the bend scene's cloth did not simulate {FRAMES} frames: {g['simulating']}, {g['frames']}")
    got = [g["body_vertices"][3 * i:3 * i + 3] for i in range(len(g["body_vertices"]) // 3)]
    want = bend_scene.skinned(FRAMES * g["dt"])
    rest = bend_scene.skinned(0.0)
    if len(got) != len(want):
        fail(f"bend: the plugin has {len(got)} body vertices, the tube {len(want)}")
    diff = max(math.dist(a, b) for a, b in zip(got, want))
    bent = max(math.dist(a, b) for a, b in zip(want, rest))
    print(f"bend, frame {FRAMES}: largest distance of the plugin's skinned body from the closed form {diff:.3g} m "
          f"(limit {MAX_DIFF_SKIN}); the bend moves it by {bent:.3g} m")
    if diff > MAX_DIFF_SKIN:
        fail("the plugin's skinned body is not where Godot skins it")
    if bent < 0.1:
        fail("bend: the bone's bend barely moves the body")


def main():
    server, lib, weft_cli, project_src, record = sys.argv[1:6]
    if not shutil.which(server):
        print(f"skipped: {server} is not installed (Debian: godot3-server)")
        sys.exit(77)
    tmp = tempfile.mkdtemp(prefix="weft_godot_", dir=os.environ.get("WEFT_TEST_TMPDIR"))
    project = os.path.join(tmp, "project")
    shutil.copytree(project_src, project)
    shutil.copy(record, project)
    with open(os.path.join(project, "weft.gdnlib")) as f:
        gdnlib = f.read()
    with open(os.path.join(project, "weft.gdnlib"), "w") as f:
        f.write(gdnlib.replace("res://bin/libweft_godot.so", os.path.abspath(lib)))

    # 1, 2: Godot against weft run: the flag, the skirt, the skirt on a skinned body, the flag
    # with scaled colliders; a skinned body against the closed form
    compare(server, project, weft_cli, tmp, "flag", weft_scene, MAX_DIFF_FLAG)
    compare(server, project, weft_cli, tmp, "skirt", skirt_scene, MAX_DIFF_SKIRT, body_variants)
    compare(server, project, weft_cli, tmp, "skinned", lambda g, t: skirt_scene(g, t, "skinned"), MAX_DIFF_SKIRT,
            body_variants)
    log = compare(server, project, weft_cli, tmp, "scaled", scaled_scene, MAX_DIFF_SCALED, scaled_variants)
    refused = ("WeftCloth 'Flag': collider '../Squashed/Shape' has a non-uniform scale (2, 0.5, 1), which would make "
               "its sphere an ellipsoid: not a collider")
    if refused not in log:
        fail(f"no error containing {refused!r}")
    check_surfaces(server, project, weft_cli, tmp)
    check_bend(server, project, tmp)

    # 3: broken settings
    b, log = run_godot(server, project, "broken", os.path.join(tmp, "broken_out.json"), tmp)
    expected = ["property stiffness_stretch = nan is not a finite number",
                "no_such_mesh.tres",
                "WeftCloth 'Lost': the MeshInstance has no mesh",
                "colliders_root 'NoSuchNode' is not a node",
                "WeftCloth 'Lines': surface 1 of its mesh is not triangles (primitive 1)",
                "WeftCloth 'NoSkeleton': attach_skeleton 'NoSuchSkeleton' is not a node",
                "WeftCloth 'NotSkeleton': attach_skeleton '../Ball' is not a Skeleton",
                "WeftCloth 'NoBone': attach_bones[0] 'nope' is not a bone of Skeleton '../Skeleton'",
                "WeftCloth 'Mismatch': attach_bones has 1 names but attach_vertices 0 vertex lists",
                "WeftCloth 'NotVertices': attach_vertices[0] is not a PoolIntArray of vertex indices",
                "WeftCloth 'NoBody': body 'NoSuchBody' is not a node: no mesh collider",
                "WeftCloth 'NotBody': body '../Ball' is not a MeshInstance: no mesh collider",
                "WeftCloth 'BadBind': body '../BadBindBody': vertex 2 is weighted to bind 3; its skin has 1 binds",
                "WeftCloth 'BadBoneName': body '../BadBoneNameBody': its Skin's bind 0 names bone 'no_such_bone', "
                "which its Skeleton does not have"]
    for e in expected:
        if e not in log:
            fail(f"no error containing {e!r}")
    if b["stiffness_stretch"] != 4000 or b["lost_simulating"] or not b["simulating"]:
        fail(f"broken settings: {b}")
    # a bad attachment or surface leaves its cloth unbuilt (it would fall off); a bad body only
    # loses the collider
    for name in ["Lines", "NoSkeleton", "NotSkeleton", "NoBone", "Mismatch", "NotVertices"]:
        if b[name + "_simulating"]:
            fail(f"{name} simulates despite its bad attachment: {b}")
    for name in ["NoBody", "NotBody", "BadBind", "BadBoneName"]:
        if not b[name + "_simulating"]:
            fail(f"{name} does not simulate: {b}")
    print("broken settings: each named in a Godot error, no crash; the flag still simulates")
    shutil.rmtree(tmp)
    print("PASS")


if __name__ == "__main__":
    main()
