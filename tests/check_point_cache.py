"""`weft run --cache` on a sheet whose OBJ `v` lines are shuffled: the PC2 and MDD files, read
here with struct (an independent reader), hold frame 0 = the file's positions and frame k = the
OBJ frame k, vertex by vertex; a bad extension and an unwritable path fail with a message and
leave no file. Usage: check_point_cache.py WEFT_CLI TMPDIR"""
import os
import random
import struct
import subprocess
import sys

cli, tmp = sys.argv[1], os.path.join(sys.argv[2], "point_cache")
os.makedirs(tmp, exist_ok=True)
N, FRAMES = 6, 4
rnd = random.Random(7)
grid = [(0.2 * (g % N), 0.0, 0.2 * (g // N)) for g in range(N * N)]
perm = list(range(N * N))
rnd.shuffle(perm)                      # file line k holds grid vertex perm[k]
where = {g: k for k, g in enumerate(perm)}
obj = os.path.join(tmp, "sheet.obj")
with open(obj, "w") as f:
    for g in perm:
        f.write("v %.6f %.6f %.6f\n" % grid[g])
    for j in range(N - 1):
        for i in range(N - 1):
            a = j * N + i
            f.write("f %s\n" % " ".join(str(where[x] + 1) for x in (a, a + 1, a + N + 1, a + N)))
scene = os.path.join(tmp, "sheet.json")
with open(scene, "w") as f:
    f.write('{"mesh": {"file": "%s"}, "pins": [{"vertices": [0, 1]}],'
            ' "time": {"fps": 30, "frames": %d}}' % (obj, FRAMES))


def run(*args):
    return subprocess.run([cli, "run", scene, "--quiet"] + list(args), capture_output=True, text=True)


def obj_vertices(path):
    with open(path) as f:
        return [tuple(map(float, l.split()[1:4])) for l in f if l.startswith("v ")]


def read_pc2(path):
    data = open(path, "rb").read()
    assert data[:12] == b"POINTCACHE2\0", data[:12]
    version, points, start, rate, samples = struct.unpack_from("<iiffi", data, 12)
    assert (version, start, rate) == (1, 0.0, 1.0), (version, start, rate)
    assert len(data) == 32 + samples * points * 12, len(data)
    return [[struct.unpack_from("<3f", data, 32 + 12 * (s * points + i)) for i in range(points)]
            for s in range(samples)]


def read_mdd(path):
    data = open(path, "rb").read()
    frames, points = struct.unpack_from(">ii", data, 0)
    times = struct.unpack_from(">%df" % frames, data, 8)
    assert all(abs(t - k / 30.0) < 1e-6 for k, t in enumerate(times)), times
    base = 8 + 4 * frames
    assert len(data) == base + frames * points * 12, len(data)
    return [[struct.unpack_from(">3f", data, base + 12 * (s * points + i)) for i in range(points)]
            for s in range(frames)]


out = os.path.join(tmp, "frames")
pc2, mdd = os.path.join(tmp, "sheet.pc2"), os.path.join(tmp, "sheet.mdd")
r = run("--out", out, "--cache", pc2)
assert r.returncode == 0, r.stderr
r = run("--cache", mdd)
assert r.returncode == 0, r.stderr
expect = [obj_vertices(obj)] + [obj_vertices(os.path.join(out, "frame_%04d.obj" % k))
                                for k in range(1, FRAMES + 1)]
for name, cache in (("pc2", read_pc2(pc2)), ("mdd", read_mdd(mdd))):
    assert len(cache) == FRAMES + 1 and all(len(s) == N * N for s in cache), name
    worst = max(abs(a - b) for s, e in zip(cache, expect) for p, q in zip(s, e) for a, b in zip(p, q))
    assert worst < 1e-6, (name, worst)        # OBJ frames print 9 significant digits
    fell = min(p[1] for p in cache[-1])
    assert fell < -0.01, (name, fell)          # the frames do move
    print("%s: %d samples x %d points, largest difference from the OBJ frames %.2g m"
          % (name, len(cache), N * N, worst))

# bad inputs: a clear message, a non-zero exit status, nothing written
for bad, words in ((os.path.join(tmp, "sheet.abc"), "must end in .pc2 or .mdd"),
                   (os.path.join(tmp, "no_such_dir", "sheet.pc2"), "cannot write")):
    r = run("--cache", bad)
    assert r.returncode != 0 and words in r.stderr, (bad, r.returncode, r.stderr)
    assert not os.path.exists(bad) and not os.path.exists(bad + ".part"), bad
print("ok")
