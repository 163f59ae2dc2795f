"""The peers driver's twirl (host_glue/blender/peer_cloth_bench.py): Blender's pinned vertices,
reported in world space, are at the rest positions turned about y by the twirl's angle at every
frame (the closed form Weft's pins follow, bench_scene_pin_transform), and the cloth is simulated
in world space: the twirled run is not the still run turned rigidly (the free vertices lag). Run with plain Python; skipped (77) without `blender`.
Usage: test_peer_twirl.py DRIVER_SCRIPT TMP_DIR"""
import array
import json
import math
import os
import shutil
import subprocess
import sys

blender = os.environ.get("WEFT_BLENDER") or shutil.which("blender")
if not blender:
    print("SKIPPED: `blender` is not installed (apt-get install blender; .ci/deps.sh does)")
    sys.exit(77)
driver, tmp = sys.argv[1], sys.argv[2]
os.makedirs(tmp, exist_ok=True)

N, FRAMES, SPIN, RAMP, FPS = 5, 12, 2 * math.pi, 0.5, 30.0
rest = [(-0.5 + i / (N - 1), 0.0, 0.3 + 0.5 * j / (N - 1)) for j in range(N) for i in range(N)]
pins = list(range(N))   # the row at z = 0.3: off the axis, so the turn moves them
obj = os.path.join(tmp, "twirl.obj")
with open(obj, "w") as f:
    for v in rest:
        f.write("v %.9g %.9g %.9g\n" % v)
    for j in range(N - 1):
        for i in range(N - 1):
            a = j * N + i + 1
            f.write("f %d %d %d %d\n" % (a, a + 1, a + 1 + N, a + N))


def run(twirl):
    job = {"mesh": obj, "pins": pins, "frames": FRAMES, "gravity": [0, -9.81, 0], "quality": 5,
           "frames_out": os.path.join(tmp, "twirl.f32")}
    if twirl:
        job["twirl"] = {"spin": SPIN, "ramp": RAMP, "fps": FPS}
    job_path, result_path = os.path.join(tmp, "twirl_job.json"), os.path.join(tmp, "twirl_result.json")
    with open(job_path, "w") as f:
        json.dump(job, f)
    cmd = [blender, "-b", "--factory-startup", "-t", "1", "--python-exit-code", "1", "--python", driver, "--",
           job_path, result_path]
    rc = subprocess.run(cmd, timeout=240, stdout=subprocess.DEVNULL).returncode
    assert rc == 0, "blender exited %d" % rc
    xs = array.array("f")
    with open(job["frames_out"], "rb") as f:
        xs.fromfile(f, FRAMES * N * N * 3)
    with open(result_path) as f:
        result = json.load(f)
    return xs, result


def angle(t):
    return SPIN * (0.5 * t * t / RAMP if t < RAMP else t - 0.5 * RAMP)


def turned(v, a):   # about y by a: Weft's column 0 is (c, 0, -s), column 2 (s, 0, c)
    c, s = math.cos(a), math.sin(a)
    return (c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2])


failures = 0
still = None
for twirl in (False, True):
    xs, result = run(twirl)
    worst_pin, least_lag = 0.0, float("inf")
    for k in range(FRAMES):   # frame start + 1 + k: time (k + 1) / fps
        a = angle((k + 1) / FPS) if twirl else 0.0
        lag = 0.0
        for p in range(N * N):
            x = xs[3 * (k * N * N + p): 3 * (k * N * N + p) + 3]
            if p in pins:
                worst_pin = max(worst_pin, math.dist(x, turned(rest[p], a)))
            elif twirl:   # against the still run's vertex turned rigidly by the same angle
                lag = max(lag, math.dist(x, turned(still[3 * (k * N * N + p): 3 * (k * N * N + p) + 3], a)))
        if twirl and k >= 4:
            least_lag = min(least_lag, lag)
    if not twirl:
        still = xs
    last = xs[3 * ((FRAMES - 1) * N * N):]
    final = result["positions"]
    same_last = max(abs(final[i] - last[i]) for i in range(3 * N * N))
    print("twirl %s: pinned vertices off the closed form by at most %.3g m; the result's positions vs the last "
          "frame %.3g m" % (twirl, worst_pin, same_last))
    if twirl:
        print("  free vertices off the still run turned rigidly: at least %.3g m from frame 5" % least_lag)
    if worst_pin > 1e-5:
        print("FAIL: pinned vertices do not follow the twirl")
        failures += 1
    if same_last > 1e-6:
        print("FAIL: the result's positions are not the last frame's")
        failures += 1
    if twirl and not least_lag > 1e-3:
        print("FAIL: the twirled cloth is the still one turned rigidly (not simulated in world space)")
        failures += 1
sys.exit(1 if failures else 0)
