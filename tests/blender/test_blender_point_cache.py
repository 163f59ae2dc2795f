"""In Blender: a mesh built from the shuffled sheet's own `v`/`f` lines (so Blender keeps the
file's vertex order), a Mesh Cache modifier reading the PC2 (then the MDD) that `weft run
--cache` wrote; at every frame k each evaluated vertex equals the OBJ frame k within 1e-5 m.
Args after --: WEFT_CLI TMPDIR (check_point_cache.py writes the files first)."""
import os
import subprocess
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
cli, tmpdir = argv[0], argv[1]
here = os.path.dirname(os.path.abspath(__file__))
subprocess.run([sys.executable if os.path.basename(sys.executable).startswith("python") else "python3",
                os.path.join(here, "..", "check_point_cache.py"), cli, tmpdir], check=True)
tmp = os.path.join(tmpdir, "point_cache")


def obj_lines(path):
    v, f = [], []
    with open(path) as fp:
        for line in fp:
            w = line.split()
            if w and w[0] == "v":
                v.append(tuple(map(float, w[1:4])))
            elif w and w[0] == "f":
                f.append([int(x.split("/")[0]) - 1 for x in w[1:]])
    return v, f


verts, faces = obj_lines(os.path.join(tmp, "sheet.obj"))
mesh = bpy.data.meshes.new("sheet")
mesh.from_pydata(verts, [], faces)
obj = bpy.data.objects.new("sheet", mesh)
bpy.context.scene.collection.objects.link(obj)
frames = 4
for ext in ("pc2", "mdd"):
    mod = obj.modifiers.new("cache", "MESH_CACHE")
    mod.cache_format = ext.upper()
    mod.filepath = os.path.join(tmp, "sheet." + ext)
    mod.forward_axis = "POS_Y"   # the file's axes as they are
    mod.up_axis = "POS_Z"
    mod.frame_start = 0.0        # scene frame k -> sample k
    mod.time_mode = "FRAME"
    worst = 0.0
    for k in range(frames + 1):
        bpy.context.scene.frame_set(k)
        dg = bpy.context.evaluated_depsgraph_get()
        ev = obj.evaluated_get(dg).to_mesh()
        want = verts if k == 0 else obj_lines(os.path.join(tmp, "frames", "frame_%04d.obj" % k))[0]
        assert len(ev.vertices) == len(want), (ext, k, len(ev.vertices))
        for v, w in zip(ev.vertices, want):
            worst = max(worst, max(abs(a - b) for a, b in zip(v.co, w)))
        obj.evaluated_get(dg).to_mesh_clear()
    print("%s: frames 0..%d, largest difference from the OBJ frames %.2g m" % (ext, frames, worst))
    assert worst < 1e-5, (ext, worst)
    obj.modifiers.remove(mod)
print("ok")
