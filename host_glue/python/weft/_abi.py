"""The ABI mirror of weft.h (plugin/include/weft/weft.h): enums, constants, every public struct
as a ctypes.Structure (checked against the C compiler by tests/python/test_python_layout.py) and
every exported function's prototype. weft/__init__.py builds the Pythonic API on top."""
import ctypes
import enum

from ctypes import (POINTER, CFUNCTYPE, c_char_p, c_double, c_float, c_int, c_int64, c_size_t,
                    c_ubyte, c_uint32, c_uint64, c_void_p)

ABI = 10                    # WEFT_ABI of the weft.h mirrored here
VERSION = (0, 10, 2)        # WEFT_VERSION_MAJOR/MINOR/PATCH of that weft.h
DEFAULT_LIBRARY = "libweft.so.10"

# ------------------------------------------------------------------------------------------------
# Enums and constants (names without their C prefix; c_constants() gives the C names)
# ------------------------------------------------------------------------------------------------


class Status(enum.IntEnum):
    OK = 0
    INVALID_ARGUMENT = 1
    OUT_OF_MEMORY = 2
    IO = 3
    IMPORT = 4
    EMPTY_MESH = 5
    NONFINITE = 6
    OUT_OF_RANGE = 7
    SOLVER_DIVERGED = 8
    SOLVER_NOT_CONVERGED = 9
    FACTORIZATION = 10
    STEP_FAILED = 11
    SCENE = 12
    ABI_MISMATCH = 13
    INVALID_HANDLE = 14
    CALL_ORDER = 15
    UNSUPPORTED = 16
    SNAPSHOT_MISMATCH = 17
    GPU = 18
    CONCURRENT_CALL = 19


class LogLevel(enum.IntEnum):
    DEBUG = 0
    INFO = 1
    WARN = 2
    ERROR = 3


class Backend(enum.IntEnum):
    AUTO = 0
    CPU = 1
    GPU = 2


class GlMode(enum.IntEnum):
    HEADLESS = 0
    HOST_CURRENT = 1


class SpringType(enum.IntEnum):
    STRETCH = 0
    SHEAR = 1
    BEND = 2


class Solver(enum.IntEnum):
    PCG = 0
    JACOBI = 1
    CHEBYSHEV = 2
    DIRECT = 3


class Preconditioner(enum.IntEnum):
    DEFAULT = 0
    BLOCK_JACOBI = 1
    AMG = 2
    IC0 = 3


class Integrator(enum.IntEnum):
    DEFAULT = 0
    BACKWARD_EULER = 1
    BDF2 = 2
    TRBDF2 = 3


class ColliderType(enum.IntEnum):
    PLANE = 0
    SPHERE = 1
    CAPSULE = 2


class Space(enum.IntEnum):
    WORLD = 0
    OBJECT = 1


FRAME_TELEPORT = 1 << 0
FRAME_RESET = 1 << 1
REPORT_POLYGON_SIDES = 8       # weft_import_report.polygons[k]: k-gons, [8] 8 or more
REPORT_MAX_WARNINGS = 16
REPORT_WARNING_LENGTH = 256
BACKEND_REASON_LENGTH = 256    # weft_cloth_info.backend_reason, terminating zero included

_ENUM_C_PREFIX = {Status: "WEFT_ERROR_", LogLevel: "WEFT_LOG_", Backend: "WEFT_BACKEND_",
                  GlMode: "WEFT_GL_", SpringType: "WEFT_SPRING_", Solver: "WEFT_SOLVER_",
                  ColliderType: "WEFT_COLLIDER_", Space: "WEFT_SPACE_", Preconditioner: "WEFT_PRECOND_",
                  Integrator: "WEFT_INTEGRATOR_"}


def c_constants():
    """{C name: value} of every constant mirrored here (compared with weft.h by the tests)."""
    out = {"WEFT_ABI": ABI, "WEFT_VERSION_MAJOR": VERSION[0], "WEFT_VERSION_MINOR": VERSION[1],
           "WEFT_VERSION_PATCH": VERSION[2], "WEFT_FRAME_TELEPORT": FRAME_TELEPORT,
           "WEFT_FRAME_RESET": FRAME_RESET, "WEFT_REPORT_POLYGON_SIDES": REPORT_POLYGON_SIDES,
           "WEFT_REPORT_MAX_WARNINGS": REPORT_MAX_WARNINGS,
           "WEFT_REPORT_WARNING_LENGTH": REPORT_WARNING_LENGTH,
           "WEFT_BACKEND_REASON_LENGTH": BACKEND_REASON_LENGTH}
    for cls, prefix in _ENUM_C_PREFIX.items():
        for member in cls:
            name = "WEFT_OK" if member is Status.OK else prefix + member.name
            out[name] = int(member)
    return out


# ------------------------------------------------------------------------------------------------
# Struct mirrors (field order, types and sizes exactly weft.h's)
# ------------------------------------------------------------------------------------------------


class _Struct(ctypes.Structure):
    def to_dict(self):
        """Fields as Python values (arrays as lists, nested structs as dicts)."""
        out = {}
        for name, _ in self._fields_:
            value = getattr(self, name)
            if isinstance(value, _Struct):
                value = value.to_dict()
            elif isinstance(value, ctypes.Array):
                value = list(value)
            out[name] = value
        return out

    def __repr__(self):
        return "%s(%s)" % (type(self).__name__,
                           ", ".join("%s=%r" % kv for kv in self.to_dict().items()))


LOG_FN = CFUNCTYPE(None, c_int, c_char_p, c_void_p)
ALLOC_FN = CFUNCTYPE(c_void_p, c_size_t, c_void_p)
FREE_FN = CFUNCTYPE(None, c_void_p, c_void_p)


class VersionInfo(_Struct):
    _fields_ = [("major", c_int), ("minor", c_int), ("patch", c_int), ("abi", c_int)]


class Allocator(_Struct):
    _fields_ = [("alloc", ALLOC_FN), ("free", FREE_FN), ("user", c_void_p)]


class ContextDef(_Struct):
    _fields_ = [("backend", c_int), ("threads", c_int), ("log", LOG_FN), ("log_user", c_void_p),
                ("log_level", c_int), ("allocator", Allocator), ("gl_mode", c_int),
                ("internal_cookie", c_uint32)]


class ClothHandle(_Struct):
    """weft_cloth: a handle by value; id 0 is the null handle."""
    _fields_ = [("id", c_uint64)]


class MeshDesc(_Struct):
    _fields_ = [("path", c_char_p), ("select", c_char_p), ("positions", POINTER(c_float)),
                ("n_vertices", c_int), ("face_sizes", POINTER(c_int)), ("n_faces", c_int),
                ("indices", POINTER(c_int))]


class Material(_Struct):
    _fields_ = [("density", c_double), ("stiffness", c_double * 3), ("damping", c_double * 3)]


class AttachmentDef(_Struct):
    _fields_ = [("vertices", POINTER(c_int)), ("n_vertices", c_int),
                ("bind_transform", c_float * 16), ("free_axis", c_float * 3),
                ("internal_cookie", c_uint32)]


class ColliderDef(_Struct):
    _fields_ = [("type", c_int), ("radius", c_double), ("half_height", c_double),
                ("thickness", c_double), ("friction", c_double), ("transform", c_float * 16),
                ("internal_cookie", c_uint32)]


class MeshColliderDef(_Struct):
    _fields_ = [("mesh", MeshDesc), ("unit_scale", c_double), ("transform", c_float * 16),
                ("thickness", c_double), ("friction", c_double), ("push_speed", c_double),
                ("internal_cookie", c_uint32)]


class ClothDef(_Struct):
    _fields_ = [("mesh", MeshDesc), ("unit_scale", c_double), ("weld_tolerance", c_double),
                ("transform", c_float * 16), ("material", Material), ("gravity", c_double * 3),
                ("wind", c_double * 3), ("air_drag_normal", c_double),
                ("air_drag_tangent", c_double), ("solver", c_int), ("tolerance", c_double),
                ("max_iterations", c_int), ("preconditioner", c_int), ("integrator", c_int),
                ("newton_iterations", c_int), ("line_search", c_int),
                ("substeps", c_int), ("max_frame_time", c_double),
                ("strain_limit", c_double), ("sleep_speed", c_double),
                ("sleep_time", c_double), ("linear_inertia", c_double),
                ("angular_inertia", c_double), ("n_attachments", c_int),
                ("attachments", POINTER(AttachmentDef)), ("n_colliders", c_int),
                ("colliders", POINTER(ColliderDef)), ("n_mesh_colliders", c_int),
                ("mesh_colliders", POINTER(MeshColliderDef)),
                # sewing (docs/design/sewing.md)
                ("sew_distance", c_double), ("sew_stiffness", c_double),
                ("seam_a", POINTER(c_int)), ("seam_b", POINTER(c_int)), ("n_seams", c_int),
                ("seam_close_time", c_double),
                ("self_collision", c_int), ("self_collision_thickness", c_double),
                ("internal_cookie", c_uint32), ("newton_forcing", c_double)]


class ClothInfo(_Struct):
    _fields_ = [("n_vertices", c_int), ("n_particles", c_int), ("n_triangles", c_int),
                ("n_springs", c_int * 3), ("n_attachments", c_int),
                ("n_pinned_particles", c_int), ("n_colliders", c_int), ("total_mass", c_double),
                ("bbox_min", c_double * 3), ("bbox_max", c_double * 3),
                ("snapshot_size", c_size_t), ("backend", c_int), ("preconditioner", c_int),
                ("integrator", c_int), ("newton_iterations", c_int), ("line_search", c_int),
                ("n_seams", c_int), ("n_panels", c_int),
                ("self_collision", c_int), ("self_collision_thickness", c_double),
                ("newton_forcing", c_double), ("tolerance", c_double), ("threads", c_int),
                ("backend_reason", ctypes.c_char * BACKEND_REASON_LENGTH)]


class Frame(_Struct):
    _fields_ = [("dt", c_double), ("object_transform", POINTER(c_float)),
                ("attachment_transforms", POINTER(c_float)),
                ("collider_transforms", POINTER(c_float)), ("wind", POINTER(c_double)),
                ("flags", c_uint32), ("mesh_collider_transforms", POINTER(c_float))]


class FrameStats(_Struct):
    _fields_ = [("ms_total", c_double), ("ms_forces", c_double), ("ms_assemble", c_double),
                ("ms_solve", c_double), ("ms_collide", c_double), ("ms_integrate", c_double),
                ("substeps", c_int), ("iterations", c_int), ("solves", c_int),
                ("ms_precond", c_double), ("max_iterations", c_int), ("residual", c_double),
                ("not_converged", c_int), ("solver", c_int),
                ("rollbacks", c_int), ("halvings", c_int), ("direct_fallbacks", c_int),
                ("failures", c_int), ("contacts", c_int), ("max_strain", c_double),
                ("kinetic_energy", c_double), ("time", c_double), ("frame", c_int64),
                ("asleep", c_int), ("fell_asleep", c_int), ("woke", c_int),
                ("self_impacts", c_int), ("self_zones", c_int), ("self_unresolved", c_int),
                ("ms_self_collide", c_double),
                # the solve, self-collision and mesh contacts in detail
                ("newton_steps", c_int), ("line_search_backtracks", c_int), ("energy_steps", c_int),
                ("friction_passes", c_int), ("bdf2_substeps", c_int), ("self_proximity", c_int),
                ("self_zone_relaxed", c_int), ("self_pairs", c_int), ("self_pairs_active", c_int),
                ("self_pair_passes", c_int), ("self_pair_overflow", c_int), ("mesh_pairs", c_int),
                ("mesh_pairs_active", c_int), ("mesh_pair_passes", c_int),
                ("mesh_pair_overflow", c_int), ("mesh_pair_skipped", c_int)]


class CollisionCheck(_Struct):
    _fields_ = [("self_intersections", c_int), ("max_penetration", c_double)]


class ClothEnergy(_Struct):
    _fields_ = [("kinetic", c_double), ("elastic", c_double), ("gravity", c_double),
                ("mass", c_double), ("center_of_mass", c_double * 3)]


class ImportReport(_Struct):
    _fields_ = [("source_vertices", c_int), ("unused_vertices", c_int), ("welded_vertices", c_int),
                ("particles", c_int), ("polygons", c_int * (REPORT_POLYGON_SIDES + 1)),
                ("triangles", c_int), ("degenerate_triangles", c_int), ("duplicate_faces", c_int),
                ("flipped_faces", c_int), ("non_orientable_components", c_int), ("edges", c_int),
                ("boundary_edges", c_int), ("non_manifold_edges", c_int), ("boundary_loops", c_int),
                ("components", c_int), ("springs", c_int * 4), ("seams", c_int), ("panels", c_int),
                ("bbox_min", c_double * 3), ("bbox_max", c_double * 3), ("unit_scale", c_double),
                ("weld_distance", c_double), ("ms_weld", c_double), ("ms_triangulate", c_double),
                ("ms_clean", c_double), ("ms_orient", c_double), ("ms_topology", c_double),
                ("ms_springs", c_double), ("ms_pattern", c_double), ("ms_total", c_double),
                ("n_warnings", c_int), ("warnings_dropped", c_int),
                ("warnings", (ctypes.c_char * REPORT_WARNING_LENGTH) * REPORT_MAX_WARNINGS)]


class MeshData(_Struct):
    _fields_ = [("n_vertices", c_int), ("n_faces", c_int), ("positions", POINTER(c_double)),
                ("face_sizes", POINTER(c_int)), ("indices", POINTER(c_int)),
                ("unit_scale", c_double)]


class RenderDef(_Struct):
    _fields_ = [("width", c_int), ("height", c_int), ("eye", c_float * 3),
                ("target", c_float * 3), ("up", c_float * 3), ("fov_y_deg", c_float),
                ("draw_colliders", c_int), ("png_path", c_char_p), ("rgba", POINTER(c_ubyte)),
                ("internal_cookie", c_uint32)]


STRUCTS = {"weft_version_info": VersionInfo, "weft_allocator": Allocator,
           "weft_context_def": ContextDef, "weft_cloth": ClothHandle,
           "weft_mesh_desc": MeshDesc, "weft_material": Material,
           "weft_attachment_def": AttachmentDef, "weft_collider_def": ColliderDef,
           "weft_mesh_collider_def": MeshColliderDef,
           "weft_cloth_def": ClothDef, "weft_cloth_info": ClothInfo, "weft_frame": Frame,
           "weft_frame_stats": FrameStats, "weft_render_def": RenderDef,
           "weft_collision_check": CollisionCheck, "weft_cloth_energy": ClothEnergy,
           "weft_import_report": ImportReport, "weft_mesh_data": MeshData}

# ------------------------------------------------------------------------------------------------
# The library
# ------------------------------------------------------------------------------------------------

_CTX = c_void_p   # weft_context*
# Every WEFT_API function of weft.h: name -> (restype, argtypes). Raw buffers are c_void_p.
PROTOTYPES = {
    "weft_version": (VersionInfo, []),
    "weft_status_string": (c_char_p, [c_int]),
    "weft_default_context_def": (ContextDef, []),
    "weft_context_create": (c_int, [c_int, POINTER(ContextDef), POINTER(c_void_p)]),
    "weft_context_destroy": (None, [_CTX]),
    "weft_context_last_error": (c_char_p, [_CTX]),
    "weft_context_last_status": (c_int, [_CTX]),
    "weft_context_backend": (c_int, [_CTX]),
    "weft_default_cloth_def": (ClothDef, []),
    "weft_default_attachment_def": (AttachmentDef, []),
    "weft_default_collider_def": (ColliderDef, []),
    "weft_default_mesh_collider_def": (MeshColliderDef, []),
    "weft_cloth_set_mesh_collider_vertices": (c_int, [_CTX, ClothHandle, c_int, c_void_p, c_int]),
    "weft_cloth_set_mesh_collider_gl_buffer": (c_int, [_CTX, ClothHandle, c_int, c_uint32, c_size_t,
                                                       c_size_t, c_int]),
    "weft_cloth_create": (c_int, [_CTX, POINTER(ClothDef), POINTER(ClothHandle)]),
    "weft_cloth_destroy": (c_int, [_CTX, ClothHandle]),
    "weft_cloth_set_attachments": (c_int, [_CTX, ClothHandle, POINTER(AttachmentDef), c_int]),
    "weft_cloth_get_info": (c_int, [_CTX, ClothHandle, POINTER(ClothInfo)]),
    "weft_cloth_check_collisions": (c_int, [_CTX, ClothHandle, POINTER(CollisionCheck)]),
    "weft_cloth_get_energy": (c_int, [_CTX, ClothHandle, POINTER(ClothEnergy)]),
    "weft_cloth_get_report": (c_int, [_CTX, ClothHandle, POINTER(ImportReport)]),
    "weft_mesh_read": (c_int, [_CTX, c_char_p, c_char_p, c_double, POINTER(MeshData)]),
    "weft_mesh_free": (None, [_CTX, POINTER(MeshData)]),
    "weft_default_frame": (Frame, []),
    "weft_cloth_step": (c_int, [_CTX, ClothHandle, POINTER(Frame), POINTER(FrameStats)]),
    "weft_context_step": (c_int, [_CTX, c_int, POINTER(ClothHandle), POINTER(Frame),
                                  POINTER(FrameStats), POINTER(c_int)]),
    "weft_cloth_get_vertices": (c_int, [_CTX, ClothHandle, c_int, c_void_p, c_void_p, c_int,
                                        POINTER(c_int)]),
    "weft_cloth_get_triangles": (c_int, [_CTX, ClothHandle, c_void_p, c_int, POINTER(c_int)]),
    "weft_cloth_write_gl_buffers": (c_int, [_CTX, ClothHandle, c_int, c_uint32, c_size_t, c_uint32,
                                            c_size_t]),
    "weft_cloth_save": (c_int, [_CTX, ClothHandle, c_void_p, c_size_t]),
    "weft_cloth_restore": (c_int, [_CTX, ClothHandle, c_void_p, c_size_t]),
    "weft_default_render_def": (RenderDef, []),
    "weft_render": (c_int, [_CTX, ClothHandle, POINTER(RenderDef)]),
}
