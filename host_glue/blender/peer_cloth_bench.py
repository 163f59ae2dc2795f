"""Blender's own cloth solver on a given mesh, timed frame by frame: the peer run of
`weft bench peers` (plugin/cli/bench/cmd_bench_peers.c), which writes the job and reads the result.

Usage: blender -b --factory-startup [-t THREADS] --python-exit-code 1 \
               --python peer_cloth_bench.py -- JOB.json RESULT.json

JOB.json:
    {"mesh": "cloth.obj",          # "v x y z" and "f a b c ..." lines only (1-based, no "/")
     "pins": [0, 31],              # 0-based vertex indices held where they are
     "frames": 60,                 # frames stepped after the start frame
     "gravity": [0, -9.81, 0],     # m/s^2, in the OBJ's own axes (no axis conversion is made)
     "quality": 5,                 # optional: the Cloth modifier's steps per frame (default 5)
     "twirl": {"spin": 6.28, "ramp": 0.5, "fps": 30},   # optional: the object turned about y (below)
     "frames_out": "frames.f32"}   # optional: every frame's positions written here (below)

The mesh is built with bpy from the OBJ as parsed here, so Blender's vertex i is OBJ vertex i and
the result lines up with the caller's particles. The object sits at the origin with no rotation
or scale; the scene's gravity is the job's, so the OBJ's axes are used as they are. A vertex
group "pins" holds the pinned vertices (weight 1). The Cloth modifier keeps every one of
Blender's defaults except quality (the job's, 5 steps per frame unless it says otherwise: also
the default in Blender 3.4) and the pin group; the settings used are read back into the result.

Twirl: the object turns about the OBJ's y axis, its rate rising evenly from 0 to `spin` rad/s over
`ramp` s and then held (`bench_scene_pin_transform`, Weft's side of it); frame start + k is keyed
at the angle of time k / fps, linearly between keys. Blender's cloth simulates in world space and
its pinned vertices follow the object, so the pins turn as Weft's do. Positions are reported in
world space (the object's matrix applied), as Weft reports its particles.

Time: Blender's cloth does not use the scene's frame rate. A frame is its unit of time (split into
`quality` steps, times `time_scale`) and it scales the scene's gravity by 0.001, so a free fall
covers 0.5 * 9.81 * 0.001 m in the first frame: as if one frame were sqrt(0.001) s = 1/31.6 s.

The file is fresh (--factory-startup, nothing saved), so the point cache is empty: the start
frame is the rest state, and every later frame_set(f), in order, runs the solver once for that
frame (the cache is freed first to be sure nothing is replayed). Each frame_set is timed with
time.perf_counter (wall) and time.process_time (the process's CPU time, all its threads); the evaluated mesh's positions after the last frame are written too. With
"frames_out", every timed frame's evaluated positions are read after its timing (outside it) and
written there as raw float32, native byte order: frames x vertices x 3, vertex order the OBJ's.

RESULT.json:
    {"blender": "3.4.1", "threads": N, "omp_num_threads": "N" (the environment's, "" unset),
     "frames": F, "ms": [... F wall times (ms) ...],
     "cpu_ms": [... F process CPU times (time.process_time, ms) ...],
     "vertices": V, "positions": [x0, y0, z0, x1, ...], "settings": {...}, "frame_range": [s, e]}
"""
import array
import json
import os
import sys
import time

import bpy


def read_obj(path):
    """Vertices (list of (x, y, z)) and faces (lists of 0-based indices) of a plain OBJ."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(tuple(float(c) for c in parts[1:4]))
            elif parts[0] == "f":
                faces.append([int(c.split("/")[0]) - 1 for c in parts[1:]])
    return verts, faces


def build_object(verts, faces, pins):
    mesh = bpy.data.meshes.new("peer_cloth")
    mesh.from_pydata(verts, [], faces)   # keeps the vertex order
    mesh.validate(verbose=False)
    mesh.update()
    if len(mesh.vertices) != len(verts):
        raise RuntimeError("mesh has %d vertices, the OBJ %d" % (len(mesh.vertices), len(verts)))
    ob = bpy.data.objects.new("peer_cloth", mesh)
    bpy.context.scene.collection.objects.link(ob)
    group = ob.vertex_groups.new(name="pins")
    group.add(list(pins), 1.0, "REPLACE")
    return ob


def twirl_angle(t, spin, ramp):
    """The angle (rad) about y at time t: the rate ramped up linearly from 0 over ramp s."""
    return spin * (0.5 * t * t / ramp if t < ramp else t - 0.5 * ramp)


def key_twirl(ob, twirl, start, frames):
    spin, ramp, fps = float(twirl["spin"]), float(twirl["ramp"]), float(twirl["fps"])
    for k in range(frames + 1):
        ob.rotation_euler = (0.0, twirl_angle(k / fps, spin, ramp), 0.0)
        ob.keyframe_insert(data_path="rotation_euler", frame=start + k)
    for curve in ob.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"


def world_positions(ob_eval, me):
    """The evaluated mesh's vertex positions in world space, flat float32."""
    co = array.array("f", [0.0]) * (3 * len(me.vertices))
    me.vertices.foreach_get("co", co)
    m = ob_eval.matrix_world
    if m == m.Identity(4):
        return co
    r = [[m[i][j] for j in range(4)] for i in range(3)]
    for v in range(0, len(co), 3):
        x, y, z = co[v], co[v + 1], co[v + 2]
        for i in range(3):
            co[v + i] = r[i][0] * x + r[i][1] * y + r[i][2] * z + r[i][3]
    return co


def setting_values(settings, names):
    return {n: getattr(settings, n) for n in names}


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 2:
        raise SystemExit("usage: blender -b --python peer_cloth_bench.py -- JOB.json RESULT.json")
    with open(argv[0]) as f:
        job = json.load(f)
    verts, faces = read_obj(job["mesh"])
    frames = int(job["frames"])
    quality = int(job.get("quality", 5))
    frames_out = job.get("frames_out")

    # an empty scene: the factory startup file's cube, camera and light removed
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    scene = bpy.context.scene
    scene.gravity = job["gravity"]
    scene.use_gravity = True

    ob = build_object(verts, faces, job["pins"])
    mod = ob.modifiers.new("Cloth", "CLOTH")
    cs = mod.settings
    cs.quality = quality
    cs.vertex_group_mass = "pins"
    start = 1
    scene.frame_start = start
    scene.frame_end = start + frames
    cache = mod.point_cache
    cache.frame_start = start
    cache.frame_end = start + frames
    if job.get("twirl"):
        key_twirl(ob, job["twirl"], start, frames)

    scene.frame_set(start)
    bpy.ops.ptcache.free_bake_all()   # nothing baked in a fresh file; make sure nothing replays
    scene.frame_set(start)            # the rest state
    ms, cpu_ms = [], []
    out = open(frames_out, "wb") if frames_out else None
    for f in range(start + 1, start + frames + 1):
        t0, c0 = time.perf_counter(), time.process_time()
        scene.frame_set(f)
        ms.append(1000.0 * (time.perf_counter() - t0))
        cpu_ms.append(1000.0 * (time.process_time() - c0))
        if out:   # outside the timed call: the evaluated mesh of this frame
            ob_eval = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
            me = ob_eval.to_mesh()
            co = world_positions(ob_eval, me)
            ob_eval.to_mesh_clear()
            co.tofile(out)
    if out:
        out.close()

    depsgraph = bpy.context.evaluated_depsgraph_get()
    ob_eval = ob.evaluated_get(depsgraph)
    me = ob_eval.to_mesh()
    positions = list(world_positions(ob_eval, me))
    n_eval = len(me.vertices)
    ob_eval.to_mesh_clear()

    settings = setting_values(cs, [
        "quality", "mass", "air_damping", "tension_stiffness", "compression_stiffness",
        "shear_stiffness", "bending_stiffness", "tension_damping", "compression_damping",
        "shear_damping", "bending_damping", "pin_stiffness", "time_scale", "bending_model"])
    settings.update(setting_values(mod.collision_settings, ["use_collision", "use_self_collision"]))
    result = {
        "blender": bpy.app.version_string,
        "threads": scene.render.threads,
        "omp_num_threads": os.environ.get("OMP_NUM_THREADS", ""),
        "frames": len(ms),
        "ms": ms,
        "cpu_ms": cpu_ms,
        "vertices": n_eval,
        "positions": positions,
        "settings": settings,
        "cache_frame_range": [cache.frame_start, cache.frame_end],
    }
    with open(argv[1], "w") as f:
        json.dump(result, f)


main()
