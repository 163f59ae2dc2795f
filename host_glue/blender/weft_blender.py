"""Weft cloth for Blender: simulates a mesh object with libweft.so, frame by frame.

Properties > Physics > Weft Cloth: "Enable Weft" on the active mesh object. On every frame change
the add-on steps the cloth and writes the result (object space) into the object's shape key
"weft" (value 1, relative to Basis); the Basis (the mesh itself) is never touched.

 - Rest shape: the evaluated mesh (modifiers and other shape keys applied, the "weft" key
   neutral) at the frame the simulation starts; it must keep the mesh's vertex count. The
   result is written before the modifier stack, so modifiers that move vertices (armature,
   lattice) are applied on top of it: drive the cloth by the object's (or its parent bone's)
   transform instead.
 - Object transform: the world matrix is decomposed; its scale (taken when the simulation
   starts) is baked into the vertices and the rigid part is weft's object transform each frame.
 - Pins: the vertices of the vertex group named in the settings (default "weft_pin", weight > 0)
   form one attachment bound to the object, or to its parent bone when it is parented to one.
 - Colliders: objects with a custom property "weft_collider" = "sphere", "capsule" or "plane",
   collected when the simulation starts; their world matrices (rigid part) are passed every
   frame. The collider's local Z axis is the capsule axis and the plane normal (weft's local Y).
   Optional custom properties: weft_radius (default: half the largest local bounding-box extent
   perpendicular to Z, times the scale), weft_half_height (capsule, default from the Z extent),
   weft_thickness, weft_friction.
 - Mesh colliders (bodies): mesh objects with "weft_collider" = "mesh": their evaluated mesh
   (modifiers applied: an armature-skinned body deforms) in world space is passed every frame
   (weft_cloth_set_mesh_collider_vertices); its vertex count must not change. The faces must be
   wound consistently (normals outwards). Optional weft_thickness, weft_friction.
 - Time: the start frame (and any frame before the one the simulation started at) resets the
   cloth. Playing forward steps one frame of 1/fps seconds. Scrubbing restores the cached
   snapshot of that frame, or the nearest earlier one and steps forward from it with the
   target frame's transforms (exact for cached frames; "Cache Frames" off keeps only the start
   snapshot).

The Weft Python bindings (host_glue/python/weft) are imported from sys.path or from ../python
next to this file; the library from the add-on preferences, else where weft.find_library looks
($WEFT_LIBRARY, the copy inside a pip-installed weft package, libweft.so.10). Blender calls the handler on its main thread, which is weft's threading contract
(one context, used by one thread).
"""
import os
import sys

import bpy
import numpy as np
from bpy.app.handlers import persistent
from mathutils import Matrix

bl_info = {
    "name": "Weft Cloth",
    "author": "Weft",
    "version": (0, 2, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Physics > Weft Cloth",
    "description": "Implicit (Baraff-Witkin) cloth simulation with libweft.so",
    "category": "Physics",
}

KEY_NAME = "weft"
COLLIDER_PROPERTY = "weft_collider"
MAX_CATCH_UP_FRAMES = 1000      # frames stepped at most to reach a frame beyond the cache

try:
    import weft
except ImportError:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
    import weft

# weft's local Y (plane normal, capsule axis) is the collider object's local Z.
_Z_UP_TO_Y_UP = Matrix.Rotation(np.pi / 2, 4, "X")


def _rigid_and_scale(matrix_world):
    """(rigid 4x4 numpy float32 matrix, scale (3,)) of a Blender world matrix."""
    loc, rot, scale = matrix_world.decompose()
    rigid = Matrix.Translation(loc) @ rot.to_matrix().to_4x4()
    return np.array(rigid, dtype=np.float32), np.array(scale, dtype=np.float32)


def _read_mesh(mesh):
    """(positions (n, 3) float32, face_sizes, indices) of a Blender mesh."""
    n = len(mesh.vertices)
    co = np.empty(n * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    m = len(mesh.polygons)
    sizes = np.empty(m, np.int32)
    starts = np.empty(m, np.int32)
    mesh.polygons.foreach_get("loop_total", sizes)
    mesh.polygons.foreach_get("loop_start", starts)
    loops = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", loops)
    if m and not np.array_equal(starts, np.concatenate(([0], np.cumsum(sizes)[:-1]))):
        loops = np.concatenate([loops[s:s + k] for s, k in zip(starts, sizes)])
    return co.reshape(n, 3), sizes, loops


def _weft_key(obj):
    """The object's "weft" shape key (created, with a Basis, when missing)."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    key = obj.data.shape_keys.key_blocks.get(KEY_NAME)
    if key is None:
        key = obj.shape_key_add(name=KEY_NAME, from_mix=False)
    key.value = 1.0
    return key


def _key_co(key_block):
    co = np.empty(len(key_block.data) * 3, np.float32)
    key_block.data.foreach_get("co", co)
    return co.reshape(-1, 3)


def _pin_matrix(obj_eval):
    """World transform the pins follow: the parent bone's when parented to one, else the object's
    (rigid part)."""
    parent = obj_eval.parent
    if parent is not None and obj_eval.parent_type == "BONE" and obj_eval.parent_bone:
        bone = parent.pose.bones.get(obj_eval.parent_bone)
        if bone is not None:
            return _rigid_and_scale(parent.matrix_world @ bone.matrix)[0]
    return _rigid_and_scale(obj_eval.matrix_world)[0]


def _collider_matrix(obj_eval):
    loc, rot, _ = obj_eval.matrix_world.decompose()
    m = Matrix.Translation(loc) @ rot.to_matrix().to_4x4() @ _Z_UP_TO_Y_UP
    return np.array(m, dtype=np.float32)


def _collider(obj, obj_eval):
    """weft.Collider for an object carrying the "weft_collider" property (custom properties are
    read from the original object, the matrix and bounding box from the evaluated one)."""
    kind = str(obj.get(COLLIDER_PROPERTY, "")).lower()
    types = {"sphere": weft.ColliderType.SPHERE, "capsule": weft.ColliderType.CAPSULE,
             "plane": weft.ColliderType.PLANE}
    if kind not in types:
        raise weft.WeftError(weft.Status.INVALID_ARGUMENT, "%s: weft_collider = %r, expected "
                             "'sphere', 'capsule' or 'plane'" % (obj.name, kind))
    corners = np.array([tuple(c) for c in obj_eval.bound_box], dtype=np.float64)
    extent = (corners.max(axis=0) - corners.min(axis=0)) * _rigid_and_scale(obj_eval.matrix_world)[1]
    c = weft.Collider(types[kind], transform=_collider_matrix(obj_eval),
                      thickness=obj.get("weft_thickness"), friction=obj.get("weft_friction"))
    if kind == "sphere":
        c.radius = obj.get("weft_radius", float(extent.max()) / 2)
    elif kind == "capsule":
        c.radius = obj.get("weft_radius", float(max(extent[0], extent[1])) / 2)
        c.half_height = obj.get("weft_half_height", max(float(extent[2]) / 2 - c.radius, 0.0))
    return c


def _is_mesh_collider(obj):
    return obj.type == "MESH" and str(obj.get(COLLIDER_PROPERTY, "")).lower() == "mesh"


def _mesh_world(obj_eval):
    """(world positions (n, 3) float32, face_sizes, indices) of an evaluated mesh object."""
    mesh = obj_eval.to_mesh()
    try:
        co, sizes, indices = _read_mesh(mesh)
    finally:
        obj_eval.to_mesh_clear()
    m = np.array(obj_eval.matrix_world, dtype=np.float64)
    world = co.astype(np.float64) @ m[:3, :3].T + m[:3, 3]
    return world.astype(np.float32), sizes, indices


def _mesh_collider(obj, obj_eval):
    """weft.MeshCollider from an evaluated mesh object, in world space (identity transform)."""
    world, sizes, indices = _mesh_world(obj_eval)
    faces = np.split(indices, np.cumsum(sizes)[:-1]) if len(sizes) else []
    return weft.MeshCollider(world, [list(f) for f in faces], thickness=obj.get("weft_thickness"),
                             friction=obj.get("weft_friction"))


class _Session:
    """One simulated object: its cloth, rest shape, baked scale and snapshot cache."""

    def __init__(self, context, obj, scene, depsgraph):
        settings = obj.weft
        key = _weft_key(obj)
        basis = _key_co(key.relative_key)
        # The evaluated mesh with the weft key neutral is the rest shape.
        key.data.foreach_set("co", basis.ravel())
        obj.data.shape_keys.update_tag()
        obj.data.update_tag()
        depsgraph.update()
        obj_eval = obj.evaluated_get(depsgraph)
        mesh = obj_eval.to_mesh()
        try:
            rest, sizes, indices = _read_mesh(mesh)
        finally:
            obj_eval.to_mesh_clear()
        if rest.shape[0] != len(obj.data.vertices):
            raise weft.WeftError(weft.Status.INVALID_ARGUMENT, "%s: the modifiers change the "
                                 "vertex count (%d -> %d); weft needs the mesh's own vertices"
                                 % (obj.name, len(obj.data.vertices), rest.shape[0]))
        rigid, self.scale = _rigid_and_scale(obj_eval.matrix_world)
        self.object_name = obj.name
        self.basis, self.rest = basis, rest
        group = obj.vertex_groups.get(settings.pin_group)
        pinned = []
        if group is not None:
            gi = group.index
            pinned = [v.index for v in obj.data.vertices
                      if any(g.group == gi and g.weight > 0 for g in v.groups)]
        self.has_pins = bool(pinned)
        self.collider_names = [o.name for o in scene.objects
                               if o is not obj and COLLIDER_PROPERTY in o and not _is_mesh_collider(o)]
        self.mesh_names = [o.name for o in scene.objects if o is not obj and _is_mesh_collider(o)]
        mesh_colliders = [_mesh_collider(scene.objects[n], scene.objects[n].evaluated_get(depsgraph))
                          for n in self.mesh_names]
        self.mesh_counts = [m.positions.shape[0] for m in mesh_colliders]
        colliders = [_collider(scene.objects[n], scene.objects[n].evaluated_get(depsgraph))
                     for n in self.collider_names]
        gravity = tuple(scene.gravity) if scene.use_gravity else (0.0, 0.0, 0.0)
        self.cloth = context.create_cloth(
            rest * self.scale, face_sizes=sizes, indices=indices, transform=rigid,
            attachments=[weft.Attachment(pinned, bind_transform=_pin_matrix(obj_eval))]
            if pinned else (),
            colliders=colliders, mesh_colliders=mesh_colliders, gravity=gravity,
            substeps=settings.substeps,
            density=settings.density, stiffness=tuple(settings.stiffness),
            strain_limit=settings.strain_limit, air_drag_normal=settings.air_drag,
            integrator=_INTEGRATORS[settings.integrator])
        self.n_vertices = rest.shape[0]
        self.start_frame = scene.frame_current
        self.frame = self.start_frame
        self.snapshots = {self.frame: self.cloth.save()}
        self.out = np.empty((self.n_vertices, 3), np.float32)

    def close(self):
        self.cloth.destroy()

    def step_to(self, scene, depsgraph, frame, use_cache):
        """Bring the cloth to frame; returns True when its positions changed."""
        if frame == self.frame:
            return False
        base = max((f for f in self.snapshots if f <= frame), default=self.start_frame)
        if frame < self.frame or base > self.frame:   # a cached frame nearer than the current
            self.cloth.restore(self.snapshots[base])
            self.frame = base
        if frame - self.frame > MAX_CATCH_UP_FRAMES:
            raise weft.WeftError(weft.Status.OUT_OF_RANGE, "frame %d is %d frames past the "
                                 "simulated ones" % (frame, frame - self.frame))
        dt = scene.render.fps_base / scene.render.fps
        obj_eval = scene.objects[self.object_name].evaluated_get(depsgraph)
        rigid = _rigid_and_scale(obj_eval.matrix_world)[0]
        pins = [_pin_matrix(obj_eval)] if self.has_pins else None
        colliders = [_collider_matrix(scene.objects[n].evaluated_get(depsgraph))
                     for n in self.collider_names if n in scene.objects]
        if len(colliders) != len(self.collider_names):
            colliders = None          # a collider was deleted: keep the last transforms
        bodies = []                   # (index, world vertices) of the mesh colliders at `frame`
        for i, n in enumerate(self.mesh_names):
            if n not in scene.objects:
                continue              # deleted: it stays where it was
            world = _mesh_world(scene.objects[n].evaluated_get(depsgraph))[0]
            if world.shape[0] != self.mesh_counts[i]:
                raise weft.WeftError(weft.Status.OUT_OF_RANGE, "%s: the mesh collider's vertex count "
                                     "changed (%d -> %d)" % (n, self.mesh_counts[i], world.shape[0]))
            bodies.append((i, world))
        while self.frame < frame:
            for i, world in bodies:
                self.cloth.set_mesh_collider_vertices(i, world)
            self.cloth.step(dt, object_transform=rigid, attachment_transforms=pins,
                            collider_transforms=colliders or None)
            self.frame += 1
            if use_cache:
                self.snapshots[self.frame] = self.cloth.save()
        return True

    def write_back(self, obj):
        """Object-space result (scale unbaked) into the weft key, as an offset from the rest so
        that other shape keys keep their effect."""
        pos = self.cloth.get_vertices(weft.Space.OBJECT, self.out)
        co = self.basis + (pos / self.scale - self.rest)
        key = _weft_key(obj)
        key.data.foreach_set("co", co.ravel())
        obj.data.shape_keys.update_tag()
        obj.data.update_tag()


class _Runtime:
    """The add-on's weft context and one session per simulated object (by name)."""

    def __init__(self):
        self.context = None
        self.sessions = {}

    def weft_context(self):
        if self.context is None:
            path = None
            addon = bpy.context.preferences.addons.get(__name__)
            if addon is not None and addon.preferences.library_path:
                path = bpy.path.abspath(addon.preferences.library_path)
            self.context = weft.Context(library=path)
        return self.context

    def drop(self, name=None):
        for key in [name] if name is not None else list(self.sessions):
            session = self.sessions.pop(key, None)
            if session is not None:
                try:
                    session.close()
                except weft.WeftError:
                    pass

    def close(self):
        self.drop()
        if self.context is not None:
            self.context.close()
            self.context = None

    def update(self, obj, scene, depsgraph):
        frame = scene.frame_current
        session = self.sessions.get(obj.name)
        if session is not None and (session.n_vertices != len(obj.data.vertices)
                                    or frame < session.start_frame
                                    or frame <= scene.frame_start):
            self.drop(obj.name)
            session = None
        if session is None:
            session = _Session(self.weft_context(), obj, scene, depsgraph)
            self.sessions[obj.name] = session
            session.write_back(obj)
            return True
        if session.step_to(scene, depsgraph, frame, obj.weft.cache_snapshots):
            session.write_back(obj)
            return True
        return False


_runtime = None


@persistent
def _on_frame_change(scene, depsgraph=None):
    if _runtime is None:
        return
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    changed = False
    for obj in scene.objects:
        if obj.type != "MESH" or not obj.weft.enabled:
            continue
        try:
            changed |= _runtime.update(obj, scene, depsgraph)
            if obj.weft.error:
                obj.weft.error = ""
        except weft.WeftError as e:
            _runtime.drop(obj.name)
            obj.weft.error = str(e)
            print("weft: %s: %s" % (obj.name, e), file=sys.stderr)
    if changed:
        depsgraph.update()   # evaluated meshes (viewport, render, exporters) see this frame


@persistent
def _on_load_pre(*_args):
    if _runtime is not None:
        _runtime.drop()


# ------------------------------------------------------------------------------------------------
# UI
# ------------------------------------------------------------------------------------------------


_INTEGRATORS = {"DEFAULT": weft.Integrator.DEFAULT, "BACKWARD_EULER": weft.Integrator.BACKWARD_EULER,
                "BDF2": weft.Integrator.BDF2, "TRBDF2": weft.Integrator.TRBDF2}


def _settings_changed(self, context):
    if _runtime is not None and context.object is not None:
        _runtime.drop(context.object.name)   # rebuilt with the new settings at the next frame


class WeftObjectSettings(bpy.types.PropertyGroup):
    enabled: bpy.props.BoolProperty(name="Weft Cloth", default=False)
    pin_group: bpy.props.StringProperty(name="Pin Group", default="weft_pin",
                                        update=_settings_changed,
                                        description="Vertex group of the pinned vertices")
    substeps: bpy.props.IntProperty(name="Substeps", default=1, min=1, max=64,
                                    update=_settings_changed)
    integrator: bpy.props.EnumProperty(
        name="Integrator", default="DEFAULT", update=_settings_changed,
        items=[("DEFAULT", "Default", "The library's choice"),
               ("BACKWARD_EULER", "Backward Euler", "First order (Baraff & Witkin)"),
               ("BDF2", "BDF2", "Second order (Choi & Ko)"),
               ("TRBDF2", "TR-BDF2", "Second order, L-stable, two stages per substep (Bank et al.)")])
    density: bpy.props.FloatProperty(name="Density", default=0.15, min=1e-4, unit="MASS",
                                     update=_settings_changed, description="kg per m^2")
    stiffness: bpy.props.FloatVectorProperty(name="Stiffness", size=3,
                                             default=(5000.0, 500.0, 50.0), min=0.0,
                                             update=_settings_changed,
                                             description="Stretch, shear, bend springs (N/m)")
    strain_limit: bpy.props.FloatProperty(name="Strain Limit", default=0.0, min=0.0, max=1.0,
                                          update=_settings_changed,
                                          description="0: off; 0.1 caps stretch at 110%")
    air_drag: bpy.props.FloatProperty(name="Air Drag", default=0.5, min=0.0,
                                      update=_settings_changed)
    cache_snapshots: bpy.props.BoolProperty(name="Cache Frames", default=True,
                                            description="Keep a snapshot of every simulated "
                                            "frame for scrubbing")
    error: bpy.props.StringProperty(name="Error", default="")


class WeftPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    library_path: bpy.props.StringProperty(
        name="libweft.so", subtype="FILE_PATH",
        description="Empty: $WEFT_LIBRARY, the weft package's copy, or libweft.so.10")

    def draw(self, context):
        self.layout.prop(self, "library_path")


class WEFT_OT_enable(bpy.types.Operator):
    """Simulate the active mesh object with Weft"""
    bl_idname = "weft.enable"
    bl_label = "Enable Weft"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and obj.mode == "OBJECT"

    def execute(self, context):
        obj = context.active_object
        _weft_key(obj)
        obj.weft.enabled = True
        obj.weft.error = ""
        if _runtime is not None:
            _runtime.drop(obj.name)
        return {"FINISHED"}


class WEFT_OT_disable(bpy.types.Operator):
    """Stop simulating the active object and remove its weft shape key"""
    bl_idname = "weft.disable"
    bl_label = "Disable Weft"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and obj.weft.enabled

    def execute(self, context):
        obj = context.active_object
        obj.weft.enabled = False
        if _runtime is not None:
            _runtime.drop(obj.name)
        keys = obj.data.shape_keys
        if keys is not None and KEY_NAME in keys.key_blocks:
            obj.shape_key_remove(keys.key_blocks[KEY_NAME])
        return {"FINISHED"}


class WEFT_OT_reset(bpy.types.Operator):
    """Forget the simulation and its cache: rebuilt from the rest shape at the next frame"""
    bl_idname = "weft.reset"
    bl_label = "Reset Weft"

    def execute(self, context):
        if _runtime is not None:
            _runtime.drop()
        return {"FINISHED"}


class WEFT_PT_cloth(bpy.types.Panel):
    bl_label = "Weft Cloth"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"

    def draw(self, context):
        layout = self.layout
        settings = context.object.weft
        if not settings.enabled:
            layout.operator("weft.enable")
            return
        row = layout.row()
        row.operator("weft.disable")
        row.operator("weft.reset")
        layout.prop_search(settings, "pin_group", context.object, "vertex_groups")
        for name in ("substeps", "integrator", "density", "stiffness", "strain_limit", "air_drag",
                     "cache_snapshots"):
            layout.prop(settings, name)
        if settings.error:
            layout.label(text=settings.error, icon="ERROR")


_CLASSES = (WeftObjectSettings, WeftPreferences, WEFT_OT_enable, WEFT_OT_disable,
            WEFT_OT_reset, WEFT_PT_cloth)


def register():
    global _runtime
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.weft = bpy.props.PointerProperty(type=WeftObjectSettings)
    _runtime = _Runtime()
    bpy.app.handlers.frame_change_post.append(_on_frame_change)
    bpy.app.handlers.load_pre.append(_on_load_pre)


def unregister():
    global _runtime
    for handlers, fn in ((bpy.app.handlers.frame_change_post, _on_frame_change),
                         (bpy.app.handlers.load_pre, _on_load_pre)):
        while fn in handlers:
            handlers.remove(fn)
    if _runtime is not None:
        _runtime.close()
        _runtime = None
    del bpy.types.Object.weft
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
