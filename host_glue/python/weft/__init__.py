"""Weft for Python: ctypes bindings of libweft.so (plugin/include/weft/weft.h, ABI 8).

    import numpy as np, weft
    with weft.Context() as ctx:          # the library: see find_library
        cloth = ctx.create_cloth(positions=P, faces=F,          # P (n, 3) float32, F (m, 4) int
                                 attachments=[weft.Attachment(pinned_vertex_indices)])
        for frame in range(60):
            cloth.step(1 / 60)
            xyz = cloth.get_vertices(out=xyz_buffer)              # fills (n, 3) float32 in place

Every public struct of weft.h has a ctypes.Structure mirror here (checked against the C compiler
by tests/python/test_python_layout.py). Failures raise WeftError(status, message) with the
context's message; the cloth is then unchanged (weft.h's contract).

Arrays: positions go in from a C-contiguous float32 array without a copy (other dtypes/orders are
converted once). get_vertices / get_triangles fill caller-provided arrays (no allocation) or
allocate one array per call. A transform is either a (4, 4) matrix m[row, col] (a C-ordered one
is converted; an F-ordered float32 one is passed as is), or 16 floats already in weft's
column-major order; stacks are (n, 4, 4) or (n, 16).

The library (find_library): Context(library=path) or Library(path), else $WEFT_LIBRARY, else the
copy inside this package (weft/libweft.so.10, put there when the package was built with
$WEFT_LIBRARY set: host_glue/python/setup.py), else libweft.so.10 on the dlopen search path. The
first that applies is opened, never a later one instead; its ABI must be this module's.

Threading: weft.h's contract. A Context and its cloths must be used by one thread at a time;
different Contexts may run on different threads (ctypes releases the GIL during each call).
"""
import ctypes
import enum
import logging
import os
import weakref

import numpy as np

from ctypes import (POINTER, CFUNCTYPE, c_char_p, c_double, c_float, c_int, c_int64, c_size_t,
                    c_ubyte, c_uint32, c_uint64, c_void_p)


# The ABI mirror (enums, structs, prototypes) lives in _abi.py.
from ._abi import *  # noqa: F401,F403  (public names of the mirror)
from ._abi import _Struct  # noqa: F401


class WeftError(Exception):
    """A failed Weft call: status (a Status) and the library's message naming the argument."""

    def __init__(self, status, message=""):
        try:
            status = Status(status)
        except ValueError:
            pass
        self.status = status
        self.message = message
        name = status.name if isinstance(status, Status) else str(status)
        super().__init__("%s: %s" % (name, message) if message else name)


_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
__version__ = "%d.%d.%d" % VERSION   # the package's version: the library version it was made for


def find_library(path=None):
    """Which libweft.so to open, as (path, source), without opening it. The first that applies:
    path ("argument"), $WEFT_LIBRARY ("WEFT_LIBRARY"), weft/libweft.so.10 inside this package
    ("package"), libweft.so.10 on the dlopen search path ("search path")."""
    if path:
        return str(path), "argument"
    if os.environ.get("WEFT_LIBRARY"):
        return os.environ["WEFT_LIBRARY"], "WEFT_LIBRARY"
    bundled = os.path.join(_PACKAGE_DIR, DEFAULT_LIBRARY)
    if os.path.isfile(bundled):
        return bundled, "package"
    return DEFAULT_LIBRARY, "search path"


class Library:
    """libweft.so opened with ctypes: every function of weft.h as an attribute, ABI checked.
    path: the file (find_library); source: how it was chosen."""

    def __init__(self, path=None):
        path, self.source = find_library(path)
        self.path = str(path)
        try:
            self.dll = ctypes.CDLL(self.path, mode=os.RTLD_NOW | os.RTLD_LOCAL)
        except OSError as e:
            message = "%s: cannot open: %s" % (self.path, e)
            if self.source == "search path":   # say everything that was looked for
                message += (" (looked for: a library argument: none; $WEFT_LIBRARY: unset; "
                            "%s in this package, %s: absent, a package built without "
                            "$WEFT_LIBRARY carries none; then %s on the dlopen search path)"
                            % (DEFAULT_LIBRARY, _PACKAGE_DIR, DEFAULT_LIBRARY))
            raise WeftError(Status.IO, message) from None
        for name, (restype, argtypes) in PROTOTYPES.items():
            try:
                fn = getattr(self.dll, name)
            except AttributeError:
                raise WeftError(Status.ABI_MISMATCH,
                                "%s: missing symbol %s" % (self.path, name)) from None
            fn.restype, fn.argtypes = restype, argtypes
            setattr(self, name, fn)
        v = self.weft_version()
        self.version = (v.major, v.minor, v.patch)
        self.abi = v.abi
        if v.abi != ABI:
            raise WeftError(Status.ABI_MISMATCH, "%s: ABI %d != %d (library %d.%d.%d != these "
                            "bindings' weft.h %d.%d.%d)" % ((self.path, v.abi, ABI) +
                                                            self.version + VERSION))

    def status_string(self, status):
        return self.weft_status_string(int(status)).decode()


def load_library(path=None):
    """Open libweft.so: path, else as find_library says."""
    return Library(path)


# ------------------------------------------------------------------------------------------------
# Array helpers
# ------------------------------------------------------------------------------------------------


def _transform16(m, name):
    """One transform as a float32 array whose memory is weft's column-major 16 floats."""
    a = np.asarray(m, dtype=np.float32)
    if a.shape == (4, 4):
        return np.asfortranarray(a)
    if a.shape == (16,):
        return np.ascontiguousarray(a)
    raise ValueError("%s: a transform is a (4, 4) matrix or 16 column-major floats, got shape %s"
                     % (name, a.shape))


def _transform_stack(m, count, name):
    """count transforms as one float32 buffer of count x 16 column-major floats."""
    a = np.asarray(m, dtype=np.float32)
    if a.ndim == 2 and a.shape == (4, 4) and count == 1:
        a = a[None]
    if a.ndim == 3 and a.shape[1:] == (4, 4):
        a = np.ascontiguousarray(a.transpose(0, 2, 1))
    elif a.ndim == 2 and a.shape[1] == 16:
        a = np.ascontiguousarray(a)
    else:
        raise ValueError("%s: expected (n, 4, 4) matrices or (n, 16) column-major floats, got "
                         "shape %s" % (name, a.shape))
    if a.shape[0] != count:
        raise WeftError(Status.INVALID_ARGUMENT, "%s: %d transforms given, the cloth has %d"
                        % (name, a.shape[0], count))
    return a


def _set_transform(field, m, name):
    field[:] = _transform16(m, name).ravel(order="K").tolist()


def _ptr(a, ctype):
    return a.ctypes.data_as(POINTER(ctype))


def _out_array(out, rows, cols, dtype, name):
    if out is None:
        return np.empty((rows, cols), dtype=dtype)
    if not isinstance(out, np.ndarray) or out.dtype != dtype or out.ndim != 2 \
            or out.shape[1] != cols or not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError("%s: expected a writeable C-contiguous %s array of shape (n, %d)"
                         % (name, np.dtype(dtype).name, cols))
    return out


class Attachment:
    """Pinned host vertices following one transform (weft_attachment_def)."""

    def __init__(self, vertices, bind_transform=None, free_axis=None):
        self.vertices = np.ascontiguousarray(vertices, dtype=np.int32).ravel()
        self.bind_transform = bind_transform
        self.free_axis = free_axis


class Collider:
    """A rigid sphere, capsule or plane (weft_collider_def); None keeps weft's default."""

    def __init__(self, type=ColliderType.SPHERE, radius=None, half_height=None, thickness=None,
                 friction=None, transform=None):
        self.type, self.radius, self.half_height = type, radius, half_height
        self.thickness, self.friction, self.transform = thickness, friction, transform


# ------------------------------------------------------------------------------------------------
# Context and Cloth
# ------------------------------------------------------------------------------------------------

_logger = logging.getLogger("weft")


class Context:
    """A weft_context. log: None (warnings to logging.getLogger("weft"); errors are raised as
    WeftError), or a callable(level: LogLevel, message: str) receiving every message at or
    above log_level."""

    def __init__(self, library=None, *, backend=Backend.AUTO, threads=0, log=None,
                 log_level=LogLevel.WARN, gl_mode=GlMode.HEADLESS):
        self._ptr = None
        self._cloths = weakref.WeakSet()   # a Cloth dropped by the host destroys its cloth
        self.lib = library if isinstance(library, Library) else load_library(library)
        self._user_log = log
        self._log_level = LogLevel(log_level)
        self._last_logged_error = ""
        self._log_fn = LOG_FN(self._on_log)   # kept alive as long as the context
        d = self.lib.weft_default_context_def()
        d.backend, d.threads, d.gl_mode = int(backend), int(threads), int(gl_mode)
        d.log, d.log_level = self._log_fn, int(min(self._log_level, LogLevel.ERROR))
        ptr = c_void_p()
        status = self.lib.weft_context_create(ABI, ctypes.byref(d), ctypes.byref(ptr))
        if status != Status.OK:
            raise WeftError(status, self._last_logged_error or self.lib.status_string(status))
        self._ptr = ptr

    def _on_log(self, level, message, _user):
        text = message.decode("utf-8", "replace") if message else ""
        if level >= LogLevel.ERROR:
            self._last_logged_error = text
        if self._user_log is not None:
            if level >= self._log_level:
                self._user_log(LogLevel(level), text)
        elif self._log_level <= level < LogLevel.ERROR:
            _logger.log({LogLevel.DEBUG: logging.DEBUG, LogLevel.INFO: logging.INFO}
                        .get(level, logging.WARNING), "%s", text)

    def _handle(self):
        if self._ptr is None:
            raise WeftError(Status.INVALID_ARGUMENT, "the weft context is closed")
        return self._ptr

    def _check(self, status):
        if status != Status.OK:
            raise WeftError(status, self.last_error)

    @property
    def last_error(self):
        return self.lib.weft_context_last_error(self._handle()).decode("utf-8", "replace")

    @property
    def last_status(self):
        return Status(self.lib.weft_context_last_status(self._handle()))

    @property
    def backend(self):
        return Backend(self.lib.weft_context_backend(self._handle()))

    def step_all(self, steps):
        """Advance many cloths of this context in one call (weft_context_step): steps is a list
        of (cloth, dt) or (cloth, dt, frame) with frame a dict of Cloth.step's keyword
        arguments. Returns one FrameStats per entry. When some cloth failed (the others still
        stepped) raises WeftError with the first failure's status and message, its `statuses`
        (a Status per entry) and `stats` attached."""
        n = len(steps)
        handles, frames, keep = (ClothHandle * n)(), (Frame * n)(), []
        for i, entry in enumerate(steps):
            cloth, dt = entry[0], entry[1]
            frame = entry[2] if len(entry) > 2 else {}
            if cloth.context is not self:
                raise WeftError(Status.INVALID_HANDLE, "steps[%d]: the cloth belongs to another "
                                "context" % i)
            handles[i] = cloth._handle if cloth._handle is not None else ClothHandle(0)
            frames[i], arrays = cloth._frame(dt, **frame)
            keep.append(arrays)
        stats, statuses = (FrameStats * n)(), (c_int * n)()
        status = self.lib.weft_context_step(self._handle(), n, handles, frames, stats, statuses)
        result = list(stats)
        if status != Status.OK:
            error = WeftError(status, self.last_error)
            error.statuses = [Status(s) for s in statuses]
            error.stats = result
            raise error
        return result

    def close(self):
        """Destroy the context and all its cloths (their Cloth objects become unusable)."""
        if self._ptr is not None:
            for cloth in list(self._cloths):
                cloth._handle = None
            self._cloths = weakref.WeakSet()
            self.lib.weft_context_destroy(self._ptr)
            self._ptr = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def read_mesh(self, path, select=None, unit_scale=1.0):
        """A mesh file as weft_cloth_create reads it (weft_mesh_read): (positions (n, 3)
        float64 in metres, face_sizes (m,) int32, indices int32, unit_scale applied)."""
        md = MeshData()
        self._check(self.lib.weft_mesh_read(self._handle(), os.fsencode(path),
                                            None if select is None else select.encode(),
                                            float(unit_scale), ctypes.byref(md)))
        try:
            pos = np.ctypeslib.as_array(md.positions, (md.n_vertices, 3)).copy()
            sizes = np.ctypeslib.as_array(md.face_sizes, (md.n_faces,)).copy()
            idx = np.ctypeslib.as_array(md.indices, (int(sizes.sum()),)).copy()
            return pos, sizes, idx, md.unit_scale
        finally:
            self.lib.weft_mesh_free(self._handle(), ctypes.byref(md))

    def create_cloth(self, positions=None, faces=None, *, face_sizes=None, indices=None,
                     path=None, select=None, transform=None, attachments=(), colliders=(),
                     seams=None, mesh_colliders=(), **params):
        """Build a cloth (weft_cloth_create) from host arrays or a mesh file.

        positions (n, 3) float32 (no copy when C-contiguous float32); the polygons either as
        faces, an (m, k) int array of k-gons or a list of index lists, or as face_sizes +
        indices (weft_mesh_desc's arrays). Or path (+ select) for a file. transform: the
        object's world transform. attachments: Attachment list; colliders: Collider list.
        seams: (k, 2) host vertex index pairs sewn together (sew_distance=D sews by distance).
        params: any other weft_cloth_def field (unit_scale, gravity=(0, -9.81, 0),
        solver=Solver.PCG, preconditioner=Preconditioner.DEFAULT, integrator=Integrator.BDF2,
        newton_iterations, line_search, substeps, strain_limit, sleep_speed, ...) and the material's density, stiffness
        and damping (3 values each, per SpringType)."""
        lib = self.lib
        d = lib.weft_default_cloth_def()
        keep = []   # every buffer d points into, alive until the call returns
        if path is not None:
            d.mesh.path = os.fsencode(path)
            if select is not None:
                d.mesh.select = select.encode()
        if positions is not None:
            pos = np.ascontiguousarray(positions, dtype=np.float32)
            if pos.ndim != 2 or pos.shape[1] != 3:
                raise ValueError("positions: expected shape (n, 3), got %s" % (pos.shape,))
            sizes, idx = _polygons(faces, face_sizes, indices)
            keep += [pos, sizes, idx]
            d.mesh.positions, d.mesh.n_vertices = _ptr(pos, c_float), pos.shape[0]
            d.mesh.face_sizes, d.mesh.n_faces = _ptr(sizes, c_int), sizes.shape[0]
            d.mesh.indices = _ptr(idx, c_int)
        if transform is not None:
            _set_transform(d.transform, transform, "transform")
        for key, value in params.items():
            target = d.material if key in ("density", "stiffness", "damping") else d
            if key not in dict(type(target)._fields_) or key in _NOT_PARAMS:
                raise TypeError("create_cloth: unknown parameter %r" % key)
            _set_field(target, key, value)
        atts = self._attachment_array(attachments, keep)
        d.n_attachments, d.attachments = len(attachments), atts
        cols = (ColliderDef * max(len(colliders), 1))()
        for i, c in enumerate(colliders):
            cols[i] = self._collider_def(c)
        d.n_colliders, d.colliders = len(colliders), cols
        if seams is not None:
            pairs = np.ascontiguousarray(seams, dtype=np.int32).reshape(-1, 2)
            sa, sb = np.ascontiguousarray(pairs[:, 0]), np.ascontiguousarray(pairs[:, 1])
            keep += [sa, sb]
            d.seam_a, d.seam_b, d.n_seams = _ptr(sa, c_int), _ptr(sb, c_int), pairs.shape[0]
        mcols = (MeshColliderDef * max(len(mesh_colliders), 1))()
        for i, m in enumerate(mesh_colliders):
            mcols[i] = self._mesh_collider_def(m, keep)
        d.n_mesh_colliders, d.mesh_colliders = len(mesh_colliders), mcols
        handle = ClothHandle()
        self._check(lib.weft_cloth_create(self._handle(), ctypes.byref(d), ctypes.byref(handle)))
        cloth = Cloth(self, handle)
        cloth._n_mesh = len(mesh_colliders)
        self._cloths.add(cloth)
        return cloth

    def _attachment_array(self, attachments, keep):
        arr = (AttachmentDef * max(len(attachments), 1))()
        for i, a in enumerate(attachments):
            ad = self.lib.weft_default_attachment_def()
            keep.append(a.vertices)
            ad.vertices, ad.n_vertices = _ptr(a.vertices, c_int), a.vertices.shape[0]
            if a.bind_transform is not None:
                _set_transform(ad.bind_transform, a.bind_transform, "bind_transform")
            if a.free_axis is not None:
                ad.free_axis[:] = [float(v) for v in a.free_axis]
            arr[i] = ad
        return arr

    def _mesh_collider_def(self, m, keep):
        md = self.lib.weft_default_mesh_collider_def()
        if m.path is not None:
            keep.append(os.fsencode(m.path))
            md.mesh.path = keep[-1]
            if m.select is not None:
                keep.append(m.select.encode())
                md.mesh.select = keep[-1]
        if m.positions is not None:
            pos = np.ascontiguousarray(m.positions, dtype=np.float32)
            if pos.ndim != 2 or pos.shape[1] != 3:
                raise ValueError("mesh collider positions: expected shape (n, 3), got %s" % (pos.shape,))
            sizes, idx = _polygons(m.faces, None, None)
            keep += [pos, sizes, idx]
            md.mesh.positions, md.mesh.n_vertices = _ptr(pos, c_float), pos.shape[0]
            md.mesh.face_sizes, md.mesh.n_faces = _ptr(sizes, c_int), sizes.shape[0]
            md.mesh.indices = _ptr(idx, c_int)
        for key in ("unit_scale", "thickness", "friction", "push_speed"):
            if getattr(m, key) is not None:
                setattr(md, key, float(getattr(m, key)))
        if m.transform is not None:
            _set_transform(md.transform, m.transform, "mesh collider transform")
        return md

    def _collider_def(self, c):
        cd = self.lib.weft_default_collider_def()
        cd.type = int(c.type)
        for key in ("radius", "half_height", "thickness", "friction"):
            if getattr(c, key) is not None:
                setattr(cd, key, float(getattr(c, key)))
        if c.transform is not None:
            _set_transform(cd.transform, c.transform, "collider transform")
        return cd


_NOT_PARAMS = {"mesh", "transform", "material", "n_attachments", "attachments", "n_colliders",
               "colliders", "n_mesh_colliders", "mesh_colliders", "internal_cookie", "seam_a", "seam_b",
               "n_seams"}


def _set_field(struct, key, value):
    current = getattr(struct, key)
    if isinstance(current, ctypes.Array):
        values = [float(v) for v in value]
        if len(values) != len(current):
            raise ValueError("%s: expected %d values, got %d" % (key, len(current), len(values)))
        current[:] = values
    elif isinstance(current, float):
        setattr(struct, key, float(value))
    else:
        setattr(struct, key, int(value))


class MeshCollider:
    """A triangle-mesh body (weft_mesh_collider_def, CPU backend): host arrays (positions (n, 3)
    and faces, as for a cloth) or a file (path, select); transform at creation; None keeps
    weft's default (thickness 0.005, friction 0.3, push_speed 0.05, unit_scale 1). Move it per frame with
    Cloth.step(mesh_collider_transforms=...) or Cloth.set_mesh_collider_vertices."""

    def __init__(self, positions=None, faces=None, *, path=None, select=None, unit_scale=None,
                 transform=None, thickness=None, friction=None, push_speed=None):
        self.positions, self.faces, self.path, self.select = positions, faces, path, select
        self.unit_scale, self.transform = unit_scale, transform
        self.thickness, self.friction, self.push_speed = thickness, friction, push_speed


def _polygons(faces, face_sizes, indices):
    """(face_sizes, indices) int32 arrays from an (m, k) array, a list of lists, or both given."""
    if face_sizes is not None or indices is not None:
        return (np.ascontiguousarray(face_sizes, dtype=np.int32).ravel(),
                np.ascontiguousarray(indices, dtype=np.int32).ravel())
    if faces is None:
        raise ValueError("positions given without faces (or face_sizes + indices)")
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        idx = np.ascontiguousarray(faces, dtype=np.int32)
        return np.full(idx.shape[0], idx.shape[1], dtype=np.int32), idx.ravel()
    sizes = np.array([len(f) for f in faces], dtype=np.int32)
    idx = np.array([i for f in faces for i in f], dtype=np.int32)
    return sizes, idx


class Cloth:
    """A cloth of a Context (weft_cloth handle). Methods raise WeftError on failure."""

    def __init__(self, context, handle):
        self.context = context
        self._handle = handle
        self._n_mesh = 0   # mesh colliders (set by create_cloth; weft_cloth_info has no count)
        self.info = self.get_info()

    def _h(self):
        if self._handle is None:
            raise WeftError(Status.INVALID_HANDLE, "the cloth was destroyed (or its context "
                            "closed)")
        return self._handle

    @property
    def handle(self):
        """The weft_cloth id (0 once destroyed)."""
        return self._handle.id if self._handle is not None else 0

    def get_info(self):
        info = ClothInfo()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_get_info(ctx._handle(), self._h(), ctypes.byref(info)))
        return info

    def check_collisions(self):
        """Crossings at the current positions: a CollisionCheck (self_intersections,
        max_penetration)."""
        out = CollisionCheck()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_check_collisions(ctx._handle(), self._h(), ctypes.byref(out)))
        return out

    def get_energy(self):
        """The current state's energies (J) and mass distribution: a ClothEnergy (kinetic,
        elastic, gravity, mass, center_of_mass)."""
        out = ClothEnergy()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_get_energy(ctx._handle(), self._h(), ctypes.byref(out)))
        return out

    def get_report(self):
        """The import report of the cloth's mesh as a dict (weft_import_report's fields; the
        warnings as a list of str)."""
        out = ImportReport()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_get_report(ctx._handle(), self._h(), ctypes.byref(out)))
        report = out.to_dict()
        report["warnings"] = [out.warnings[k].value.decode("utf-8", "replace")
                              for k in range(out.n_warnings)]
        return report

    def destroy(self):
        if self._handle is not None and self.context._ptr is not None:
            ctx = self.context
            ctx._check(ctx.lib.weft_cloth_destroy(ctx._handle(), self._handle))
            ctx._cloths.discard(self)
        self._handle = None

    def __del__(self):
        try:
            self.destroy()
        except Exception:
            pass

    def set_attachments(self, attachments):
        ctx, keep = self.context, []
        arr = ctx._attachment_array(attachments, keep)
        ctx._check(ctx.lib.weft_cloth_set_attachments(ctx._handle(), self._h(), arr,
                                                      len(attachments)))
        self.info = self.get_info()

    def _frame(self, dt, *, object_transform=None, attachment_transforms=None,
               collider_transforms=None, wind=None, teleport=False, reset=False, flags=0,
               mesh_collider_transforms=None):
        """A Frame of step's arguments and the arrays it points into (keep them alive)."""
        fr = self.context.lib.weft_default_frame()
        fr.dt = float(dt)
        fr.flags = int(flags) | (FRAME_TELEPORT if teleport else 0) | (FRAME_RESET if reset else 0)
        keep = []
        if object_transform is not None:
            keep.append(_transform16(object_transform, "object_transform"))
            fr.object_transform = _ptr(keep[-1], c_float)
        if attachment_transforms is not None:
            keep.append(_transform_stack(attachment_transforms, self.info.n_attachments,
                                         "attachment_transforms"))
            fr.attachment_transforms = _ptr(keep[-1], c_float)
        if collider_transforms is not None:
            keep.append(_transform_stack(collider_transforms, self.info.n_colliders,
                                         "collider_transforms"))
            fr.collider_transforms = _ptr(keep[-1], c_float)
        if mesh_collider_transforms is not None:
            keep.append(_transform_stack(mesh_collider_transforms, self._n_mesh,
                                         "mesh_collider_transforms"))
            fr.mesh_collider_transforms = _ptr(keep[-1], c_float)
        if wind is not None:
            keep.append(np.array(wind, dtype=np.float64).reshape(3))
            fr.wind = _ptr(keep[-1], c_double)
        return fr, keep

    def step(self, dt, **frame):
        """Advance by dt seconds (weft_cloth_step). Keyword arguments: object_transform,
        attachment_transforms, collider_transforms, mesh_collider_transforms (at the end of the
        frame; None: unchanged), wind, teleport, reset, flags. Returns the FrameStats."""
        ctx = self.context
        fr, _keep = self._frame(dt, **frame)
        stats = FrameStats()
        ctx._check(ctx.lib.weft_cloth_step(ctx._handle(), self._h(), ctypes.byref(fr),
                                           ctypes.byref(stats)))
        return stats

    def set_mesh_collider_vertices(self, index, positions):
        """Mesh collider index's world vertex positions (n, 3) at the end of the next frame
        (weft_cloth_set_mesh_collider_vertices: a deforming body)."""
        ctx = self.context
        pos = np.ascontiguousarray(positions, dtype=np.float32)
        if pos.ndim != 2 or pos.shape[1] != 3:
            raise ValueError("positions: expected shape (n, 3), got %s" % (pos.shape,))
        ctx._check(ctx.lib.weft_cloth_set_mesh_collider_vertices(ctx._handle(), self._h(), int(index),
                                                                 _ptr(pos, c_float), pos.shape[0]))

    def get_vertices(self, space=Space.WORLD, out=None, *, normals=False, normals_out=None):
        """Positions per host vertex as (n, 3) float32, written into out when given (a
        writeable C-contiguous float32 (capacity, 3) array; no allocation), else into one new
        array. normals=True (or normals_out) returns (positions, normals)."""
        n = self.info.n_vertices
        pos = _out_array(out, n, 3, np.float32, "out")
        want_normals = normals or normals_out is not None
        nrm = _out_array(normals_out, n, 3, np.float32, "normals_out") if want_normals else None
        if nrm is not None and nrm.shape[0] != pos.shape[0]:
            raise ValueError("normals_out: expected %d rows like out" % pos.shape[0])
        count = c_int()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_get_vertices(
            ctx._handle(), self._h(), int(space), pos.ctypes.data,
            nrm.ctypes.data if nrm is not None else None, pos.shape[0], ctypes.byref(count)))
        return (pos, nrm) if want_normals else pos

    def get_triangles(self, out=None):
        """Simulated triangles as (n_triangles, 3) int32 host vertex indices."""
        idx = _out_array(out, self.info.n_triangles, 3, np.int32, "out")
        count = c_int()
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_get_triangles(ctx._handle(), self._h(), idx.ctypes.data,
                                                    idx.shape[0], ctypes.byref(count)))
        return idx

    def save(self, out=None):
        """The whole mutable state (weft_cloth_save) as bytes, or written into out (a
        writeable buffer of at least info.snapshot_size bytes), which is returned."""
        size = self.info.snapshot_size
        ctx = self.context
        if out is None:
            buf = ctypes.create_string_buffer(size)
            ctx._check(ctx.lib.weft_cloth_save(ctx._handle(), self._h(), buf, size))
            return buf.raw
        view = np.frombuffer(out, dtype=np.uint8)
        if not view.flags.writeable:
            raise ValueError("out: the snapshot buffer must be writeable")
        ctx._check(ctx.lib.weft_cloth_save(ctx._handle(), self._h(), view.ctypes.data,
                                           view.nbytes))
        return out

    def restore(self, snapshot):
        """Restore a snapshot from save() (any bytes-like object; no copy)."""
        view = np.frombuffer(snapshot, dtype=np.uint8)
        ctx = self.context
        ctx._check(ctx.lib.weft_cloth_restore(ctx._handle(), self._h(),
                                              view.ctypes.data if view.nbytes else None,
                                              view.nbytes))

    def render(self, width=640, height=480, *, png_path=None, rgba=False, eye=None, target=None,
               up=None, fov_y_deg=None, draw_colliders=True):
        """Preview picture (weft_render): written to png_path and/or returned as an
        (height, width, 4) uint8 array when rgba is True (or an array to fill)."""
        ctx = self.context
        d = ctx.lib.weft_default_render_def()
        d.width, d.height, d.draw_colliders = int(width), int(height), int(bool(draw_colliders))
        for key, value in (("eye", eye), ("target", target), ("up", up)):
            if value is not None:
                getattr(d, key)[:] = [float(v) for v in value]
        if fov_y_deg is not None:
            d.fov_y_deg = float(fov_y_deg)
        if png_path is not None:
            d.png_path = os.fsencode(png_path)
        image = None
        if rgba is not False and rgba is not None:
            image = np.empty((height, width, 4), np.uint8) if rgba is True else rgba
            if image.shape != (height, width, 4) or image.dtype != np.uint8 \
                    or not image.flags.c_contiguous or not image.flags.writeable:
                raise ValueError("rgba: expected a writeable C-contiguous uint8 array of shape "
                                 "(%d, %d, 4)" % (height, width))
            d.rgba = _ptr(image, c_ubyte)
        ctx._check(ctx.lib.weft_render(ctx._handle(), self._h(), ctypes.byref(d)))
        return image
