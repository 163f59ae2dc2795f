"""host_glue/python/weft against the built libweft.so ($WEFT_LIBRARY): a grid cloth from NumPy
arrays, stepped, read back into caller arrays; results checked against closed forms (free fall,
flat normals, pins carried by a transform, a sphere's surface), snapshots restored bit for bit, and
bad calls raising WeftError with the library's message and leaving the cloth as it was."""
import os
import sys
import unittest

import numpy as np

import weft

G = 9.81
H = 1.0 / 60.0


def grid(n=6, spacing=0.1, height=1.0):
    """n x n vertices in the xz plane at y = height, quads counter-clockwise seen from +y."""
    i, k = np.meshgrid(np.arange(n), np.arange(n))
    pos = np.stack([i.ravel() * spacing, np.full(n * n, height), k.ravel() * spacing], axis=1)
    v = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    faces = np.stack([v, v + n, v + n + 1, v + 1], axis=1)
    return pos.astype(np.float32), faces.astype(np.int32)


def translation(x, y, z):
    m = np.eye(4, dtype=np.float32)
    m[:3, 3] = (x, y, z)
    return m


class RoundTrip(unittest.TestCase):
    def setUp(self):
        self.ctx = weft.Context()
        self.pos, self.faces = grid()

    def tearDown(self):
        self.ctx.close()

    def make(self, **kw):
        kw.setdefault("air_drag_normal", 0.0)
        kw.setdefault("air_drag_tangent", 0.0)
        return self.ctx.create_cloth(self.pos, self.faces, **kw)

    def test_library_version(self):
        lib = self.ctx.lib
        self.assertEqual(lib.abi, weft.ABI)
        self.assertEqual(lib.version, weft.VERSION)
        self.assertEqual(lib.status_string(weft.Status.IMPORT), "mesh import failed")
        self.assertIn(self.ctx.backend, (weft.Backend.CPU, weft.Backend.GPU))

    def test_free_fall_into_caller_arrays(self):
        cloth = self.make()
        info = cloth.info
        self.assertEqual(info.n_vertices, 36)
        self.assertEqual(info.n_triangles, 50)
        self.assertAlmostEqual(info.total_mass, 0.15 * 0.5 * 0.5, places=9)  # density x area
        for _ in range(10):
            stats = cloth.step(H)
        self.assertEqual(stats.frame, 10)
        self.assertAlmostEqual(stats.time, 10 * H, places=12)
        out = np.zeros((36, 3), np.float32)
        nrm = np.zeros((36, 3), np.float32)
        got, got_n = cloth.get_vertices(weft.Space.WORLD, out, normals_out=nrm)
        self.assertIs(got, out)        # filled in place, nothing allocated
        self.assertIs(got_n, nrm)
        drop = G * H * H * 10 * 11 / 2   # backward Euler: sum of h * (n h g)
        np.testing.assert_allclose(out[:, [0, 2]], self.pos[:, [0, 2]], atol=1e-5)
        np.testing.assert_allclose(out[:, 1], 1.0 - drop, atol=1e-4)
        np.testing.assert_allclose(nrm, np.tile([0, 1, 0], (36, 1)), atol=1e-5)  # flat, +y
        # object space = the host's mesh (identity object transform): the same numbers
        np.testing.assert_array_equal(cloth.get_vertices(weft.Space.OBJECT), out)

    def test_energy_report_and_mesh_file(self):
        """weft_cloth_get_energy in free fall (backward Euler loses what it gains in kinetic
        energy), weft_cloth_get_report of a grid, weft_mesh_read of an OBJ the test writes; a bad
        path raises with the library's message."""
        cloth = self.make()
        e0 = cloth.get_energy()
        self.assertAlmostEqual(e0.mass, cloth.info.total_mass, places=12)
        self.assertEqual(e0.kinetic, 0.0)
        cloth.step(H)
        e1 = cloth.get_energy()
        self.assertAlmostEqual(e1.kinetic, 0.5 * e1.mass * (G * H) ** 2, delta=1e-3 * e1.kinetic)
        total0 = e0.kinetic + e0.elastic + e0.gravity
        total1 = e1.kinetic + e1.elastic + e1.gravity
        self.assertAlmostEqual(total1, total0 - e1.kinetic, delta=1e-3 * e1.kinetic)
        report = cloth.get_report()
        self.assertEqual(report["particles"], 36)
        self.assertEqual(report["polygons"][4], 25)
        self.assertEqual(report["springs"][0], 60)
        self.assertIsInstance(report["warnings"], list)
        path = os.path.join(os.environ.get("WEFT_TEST_TMPDIR", "/tmp"), "python_read_mesh.obj")
        with open(path, "w") as f:
            f.write("v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4\n")
        pos, sizes, idx, scale = self.ctx.read_mesh(path, unit_scale=0.5)
        np.testing.assert_array_equal(pos, [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
        np.testing.assert_array_equal(sizes, [4])
        np.testing.assert_array_equal(idx, [0, 1, 2, 3])
        self.assertEqual(scale, 0.5)
        with self.assertRaises(weft.WeftError) as e:
            self.ctx.read_mesh(path + ".missing")
        self.assertEqual(e.exception.status, weft.Status.IO)
        self.assertIn("python_read_mesh.obj.missing", e.exception.message)

    def test_seams(self):
        # two copies of the grid, the second 1 mm above: sew_distance sews every boundary
        # vertex of one to the other's boundary; a host pair sews a vertex to itself: refused
        pos2 = np.concatenate([self.pos, self.pos + np.float32([0, 0.001, 0])])
        faces2 = np.concatenate([self.faces, self.faces + len(self.pos)])
        cloth = self.ctx.create_cloth(pos2, faces2, sew_distance=0.002)
        self.assertEqual(cloth.info.n_panels, 1)
        self.assertEqual(cloth.info.n_seams, 20)      # 20 boundary vertex pairs, each once
        cloth = self.ctx.create_cloth(pos2, faces2, seams=[[0, 36], [5, 41]])
        self.assertEqual((cloth.info.n_seams, cloth.info.n_panels), (2, 1))
        with self.assertRaises(weft.WeftError) as e:
            self.ctx.create_cloth(pos2, faces2, seams=[[3, 3]])
        self.assertIn("seam", str(e.exception))
    def test_self_collision_settings_and_check(self):
        """self_collision through ClothDef, the resolved setting, the frame stats' fields and
        weft_cloth_check_collisions; a bad thickness refused with the field's name. Either
        backend (AUTO picks the GPU on a real GPU: core's stage on the host there)."""
        cloth = self.make(self_collision=1, self_collision_thickness=0.004)
        info = cloth.info
        self.assertEqual(info.self_collision, 1)
        self.assertAlmostEqual(info.self_collision_thickness, 0.004)
        stats = cloth.step(H)
        self.assertEqual(stats.self_unresolved, 0)
        self.assertGreaterEqual(stats.ms_self_collide, 0.0)
        check = cloth.check_collisions()
        self.assertEqual(check.self_intersections, 0)
        self.assertEqual(check.max_penetration, 0.0)
        self.assertEqual(self.make().info.self_collision, 0)   # the default for a plain cloth
        with self.assertRaises(weft.WeftError) as e:
            self.make(self_collision=1, self_collision_thickness=-1.0)
        self.assertEqual(e.exception.status, weft.Status.INVALID_ARGUMENT)
        self.assertIn("self_collision_thickness", e.exception.message)

    def test_triangles_cover_the_quads(self):
        cloth = self.make()
        tris = cloth.get_triangles()
        self.assertEqual(tris.shape, (50, 3))
        self.assertEqual(tris.dtype, np.int32)
        quads = [set(f) for f in self.faces.tolist()]
        for t in tris.tolist():
            self.assertTrue(any(set(t) <= q for q in quads), t)
        self.assertEqual(set(tris.ravel().tolist()), set(range(36)))

    def test_pins_follow_their_transform(self):
        pinned = np.arange(6)
        cloth = self.make(attachments=[weft.Attachment(pinned)])
        self.assertEqual(cloth.info.n_pinned_particles, 6)
        for frame in range(1, 21):
            m = translation(0.01 * frame, 0.0, 0.0)      # (4, 4), translation in column 3
            if frame % 2:
                m = np.asfortranarray(m).ravel(order="F")  # or 16 column-major floats
            cloth.step(H, attachment_transforms=[m])
        out = cloth.get_vertices()
        expected = self.pos[pinned] + np.float32([0.2, 0.0, 0.0])
        np.testing.assert_allclose(out[pinned], expected, atol=1e-5)
        self.assertTrue(np.all(out[30:, 1] < 0.95))       # the free edge swung down

    def test_sphere_collider(self):
        center = np.array([0.25, 0.7, 0.25])
        radius = 0.15
        cloth = self.make(colliders=[weft.Collider(weft.ColliderType.SPHERE, radius=radius,
                                                   transform=translation(*center))])
        self.assertEqual(cloth.info.n_colliders, 1)
        contacts = 0
        for _ in range(75):
            stats = cloth.step(H)
            contacts = max(contacts, stats.contacts)
        out = cloth.get_vertices()
        dist = np.linalg.norm(out - center, axis=1)
        self.assertGreater(contacts, 0)
        self.assertGreaterEqual(dist.min(), radius - 1e-3)   # nothing inside the sphere
        self.assertLess(out[:, 1].min(), center[1])           # the corners hang below its middle

    def test_mesh_collider(self):
        # a box 0.3 m wide under the middle of the sheet, as host triangles, then raised by its
        # vertices (a deforming body) and by a transform; no vertex ever inside it
        lo, hi = np.array([0.1, 0.5, 0.1]), np.array([0.4, 0.8, 0.4])
        corners = np.array([[hi[a] if (k >> a) & 1 else lo[a] for a in range(3)] for k in range(8)],
                           dtype=np.float32)
        quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]
        tris = np.array([t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])],
                        dtype=np.int32)
        cloth = self.make(mesh_colliders=[weft.MeshCollider(corners, tris, friction=0.5)])

        def inside(out, dy):
            return np.all((out > lo + [0, dy, 0]) & (out < hi + [0, dy, 0]), axis=1).sum()

        for _ in range(60):
            cloth.step(H)
            self.assertEqual(inside(cloth.get_vertices(), 0.0), 0)
        for f in range(10):
            cloth.set_mesh_collider_vertices(0, corners + [0, 0.01 * (f + 1), 0])
            cloth.step(H)
            self.assertEqual(inside(cloth.get_vertices(), 0.01 * (f + 1)), 0)
        cloth.step(H, mesh_collider_transforms=[translation(0, 0.15, 0)])
        out = cloth.get_vertices()
        self.assertEqual(inside(out, 0.15), 0)
        self.assertGreater(out[:, 1].max(), hi[1] + 0.15)
        with self.assertRaises(weft.WeftError) as e:
            cloth.set_mesh_collider_vertices(0, corners[:7])
        self.assertEqual(e.exception.status, weft.Status.OUT_OF_RANGE)

    def test_snapshot_restores_bit_for_bit(self):
        cloth = self.make(attachments=[weft.Attachment([0, 5])])
        for _ in range(5):
            cloth.step(H, wind=(1.0, 0.0, 0.5))
        snap = cloth.save()
        self.assertIsInstance(snap, bytes)
        self.assertEqual(len(snap), cloth.info.snapshot_size)
        buf = bytearray(len(snap))
        self.assertIs(cloth.save(buf), buf)
        self.assertEqual(bytes(buf), snap)
        for _ in range(5):
            cloth.step(H, attachment_transforms=[translation(0, 0.05, 0)])
        first = cloth.get_vertices()
        cloth.restore(snap)
        self.assertEqual(cloth.save(), snap)
        for _ in range(5):
            cloth.step(H, attachment_transforms=[translation(0, 0.05, 0)])
        self.assertEqual(cloth.get_vertices().tobytes(), first.tobytes())
        cloth.restore(memoryview(bytearray(snap)))     # any bytes-like object
        self.assertEqual(cloth.save(), snap)

    def test_errors_raise_with_the_message_and_change_nothing(self):
        cloth = self.make()
        cloth.step(H)
        before, snap = cloth.get_vertices(), cloth.save()
        with self.assertRaises(weft.WeftError) as e:
            cloth.step(-1.0)
        self.assertEqual(e.exception.status, weft.Status.INVALID_ARGUMENT)
        self.assertIn("dt", e.exception.message)
        self.assertEqual(e.exception.message, self.ctx.last_error)
        print("\n  step(-1):", e.exception, file=sys.stderr)
        with self.assertRaises(weft.WeftError) as e:
            cloth.restore(snap[: len(snap) // 2])
        self.assertIn(e.exception.status, (weft.Status.INVALID_ARGUMENT,
                                           weft.Status.SNAPSHOT_MISMATCH))
        print("  restore(half a snapshot):", e.exception, file=sys.stderr)
        with self.assertRaises(weft.WeftError) as e:
            cloth.get_vertices(out=np.zeros((35, 3), np.float32))
        self.assertEqual(e.exception.status, weft.Status.OUT_OF_RANGE)
        with self.assertRaises(weft.WeftError) as e:   # checked here: C would read past the end
            cloth.step(H, attachment_transforms=[np.eye(4)])
        self.assertEqual(e.exception.status, weft.Status.INVALID_ARGUMENT)
        with self.assertRaises(ValueError):
            cloth.get_vertices(out=np.zeros((36, 3), np.float64))
        self.assertEqual(cloth.get_vertices().tobytes(), before.tobytes())
        self.assertEqual(cloth.save(), snap)

        with self.assertRaises(weft.WeftError) as e:
            self.ctx.create_cloth(self.pos, np.where(self.faces == 7, 99, self.faces))
        self.assertEqual(e.exception.status, weft.Status.OUT_OF_RANGE)
        self.assertIn("99", e.exception.message)
        print("  index 99 of 36 vertices:", e.exception, file=sys.stderr)

        cloth.destroy()
        with self.assertRaises(weft.WeftError) as e:
            cloth.step(H)
        self.assertEqual(e.exception.status, weft.Status.INVALID_HANDLE)

    def test_step_all_is_the_single_steps(self):
        # three cloths in one weft_context_step per frame against the same cloths stepped one by
        # one (weft_cloth_step) in a second context: the same positions, bit for bit
        other = weft.Context(threads=self.ctx_threads())
        try:
            kws = [dict(attachments=[weft.Attachment([0, 5])]), dict(), dict(solver=weft.Solver.JACOBI)]
            batch = [self.make(**kw) for kw in kws]
            alone = [other.create_cloth(self.pos, self.faces, air_drag_normal=0.0,
                                        air_drag_tangent=0.0, **kw) for kw in kws]
            for f in range(8):
                pin = dict(attachment_transforms=[translation(0.01 * f, 0.0, 0.0)])
                frames = [pin, dict(wind=(1.0, 0.0, 0.0)), dict()]
                stats = self.ctx.step_all([(c, H, fr) for c, fr in zip(batch, frames)])
                self.assertEqual([s.frame for s in stats], [f + 1] * 3)
                for c, fr in zip(alone, frames):
                    c.step(H, **fr)
            for a, b in zip(batch, alone):
                self.assertEqual(a.get_vertices().tobytes(), b.get_vertices().tobytes())
            # a bad entry: reported at its index, the others still step, the bad one unchanged
            snap = batch[1].save()
            with self.assertRaises(weft.WeftError) as e:
                self.ctx.step_all([(batch[0], H), (batch[1], float("nan")), (batch[2], H)])
            self.assertEqual(e.exception.status, weft.Status.NONFINITE)
            self.assertEqual(e.exception.statuses, [weft.Status.OK, weft.Status.NONFINITE,
                                                    weft.Status.OK])
            self.assertIn("frames[1].dt is NaN", e.exception.message)
            self.assertEqual(e.exception.stats[0].frame, 9)
            self.assertEqual(batch[1].save(), snap)
            print("\n  step_all with a NaN dt at 1:", e.exception, file=sys.stderr)
        finally:
            other.close()

    def ctx_threads(self):
        return 0   # both contexts on OpenMP's default, as setUp's

    def test_abi_mismatch_and_bad_library(self):
        lib = self.ctx.lib
        d = lib.weft_default_context_def()
        ptr = weft.c_void_p()
        status = lib.weft_context_create(weft.ABI + 1, d, weft.ctypes.byref(ptr))
        self.assertEqual(status, weft.Status.ABI_MISMATCH)
        self.assertIsNone(ptr.value)
        with self.assertRaises(weft.WeftError) as e:
            weft.Context(library="/nonexistent/libweft.so")
        self.assertEqual(e.exception.status, weft.Status.IO)
        self.assertIn("/nonexistent/libweft.so: cannot open", e.exception.message)

    def test_render_into_an_array_and_a_png(self):
        """weft_render through the RenderDef mirror: the sheet seen from above fills the centre
        with its front colour (red), the sky (blue) the corners; the PNG has its signature."""
        cloth = self.make()
        if os.environ.get("WEFT_GPU") == "OFF":        # built without gpu/: refused, said so
            with self.assertRaises(weft.WeftError) as e:
                cloth.render(64, 48, rgba=True)
            self.assertEqual(e.exception.status, weft.Status.UNSUPPORTED)
            return
        image = np.zeros((48, 64, 4), np.uint8)
        png = os.path.join(os.environ.get("WEFT_TEST_TMPDIR", "/tmp"), "python_render.png")
        out = cloth.render(64, 48, rgba=image, png_path=png, eye=(0.25, 3.0, 0.25),
                           target=(0.25, 1.0, 0.25), up=(0.0, 0.0, -1.0), fov_y_deg=30.0)
        self.assertIs(out, image)                        # filled in place
        r, g, b, a = (int(v) for v in image[24, 32])
        self.assertTrue(r > g and r > b, "centre pixel %s is not the red front" % image[24, 32])
        r, g, b, a = (int(v) for v in image[0, 0])
        self.assertTrue(b > r and b > 150, "corner pixel %s is not the blue sky" % image[0, 0])
        self.assertTrue((image[..., 3] == 255).all())
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        with self.assertRaises(weft.WeftError) as e:
            cloth.render(0, 48)
        self.assertEqual(e.exception.status, weft.Status.INVALID_ARGUMENT)
        self.assertIn("width", e.exception.message)

    def test_foreign_libraries_refused(self):
        """The loader's fixtures (tests/loader_fixtures): no weft symbols; every symbol but
        weft_version() reporting another ABI."""
        path = os.environ["WEFT_FIXTURE_NO_SYMBOLS"]
        with self.assertRaises(weft.WeftError) as e:
            weft.Library(path)
        self.assertEqual(e.exception.status, weft.Status.ABI_MISMATCH)
        self.assertEqual(e.exception.message, path + ": missing symbol weft_version")
        path, abi = os.environ["WEFT_FIXTURE_OLD_ABI"], int(os.environ["WEFT_FIXTURE_ABI"])
        with self.assertRaises(weft.WeftError) as e:
            weft.Context(library=path)
        self.assertEqual(e.exception.status, weft.Status.ABI_MISMATCH)
        self.assertIn("%s: ABI %d != %d (" % (path, abi, weft.ABI), e.exception.message)
        print("\n ", e.exception, file=sys.stderr)

    def test_logger_and_closed_context(self):
        messages = []
        ctx = weft.Context(log=lambda level, text: messages.append((level, text)),
                           log_level=weft.LogLevel.DEBUG)
        cloth = ctx.create_cloth(self.pos, self.faces)
        with self.assertRaises(weft.WeftError):
            cloth.step(0.0)
        self.assertIn(weft.LogLevel.ERROR, [m[0] for m in messages])
        ctx.close()
        with self.assertRaises(weft.WeftError):
            cloth.step(H)
        with self.assertRaises(weft.WeftError):
            ctx.create_cloth(self.pos, self.faces)

    def test_parameters_reach_the_library(self):
        cloth = self.make(gravity=(0.0, 0.0, 0.0), wind=(0.0, 0.0, 0.0), density=0.3,
                          solver=weft.Solver.DIRECT, substeps=2)
        self.assertAlmostEqual(cloth.info.total_mass, 0.3 * 0.25, places=9)
        stats = cloth.step(H)
        self.assertEqual(stats.solver, weft.Solver.DIRECT)
        self.assertEqual(stats.substeps, 2)
        np.testing.assert_array_equal(cloth.get_vertices(), self.pos)   # no force: at rest
        with self.assertRaises(TypeError):
            self.make(no_such_parameter=1)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
