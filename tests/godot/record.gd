# Run by test_godot.py: `godot3-server --path PROJECT -s res://record.gd` with
#   WEFT_GODOT_MODE=flag    step flag.tscn for WEFT_GODOT_FRAMES physics frames, then write the
#                           Flag's rest mesh, settings, colliders and its mesh's vertices (read
#                           back from the node's ArrayMesh) as JSON to WEFT_GODOT_OUT, and quit
#   WEFT_GODOT_MODE=skirt   the same for skirt.tscn's Skirt (attached to a bone, a body mesh
#                           collider), with the waist vertices, the body's mesh and transform
#   WEFT_GODOT_MODE=skinned the same for skinned_skirt.tscn (the body skinned to a turning bone)
#   WEFT_GODOT_MODE=scaled  flag.tscn with scaled colliders: the flag as for flag, and each
#                           collider's shape sizes and global transform
#   WEFT_GODOT_MODE=surfaces flag.tscn with its mesh split into two surfaces: the flag as for
#                           flag (its one-surface rest mesh and pins), its pins in the surfaces
#                           joined, and each surface's material, arrays and final vertices
#   WEFT_GODOT_MODE=bend    bend.tscn (written by test_godot.py): its Cloth's frames and the body
#                           vertices the plugin skinned (get_body_vertices)
#   WEFT_GODOT_MODE=broken  broken settings (a NaN property, a mesh path that does not exist, a
#                           colliders_root that names no node, bad bone attachments and bodies,
#                           skinned bodies with a bad skin, a surface of lines):
#                           step a few frames, write what the nodes report, quit
extends SceneTree

var mode = ""
var out_path = ""
var n_frames = 0
var flag = null
var rest = null
var broken = []
var body = null
var ticks = 0
var pinned = null
var flag_rest_surfaces = []

func _initialize():
	mode = OS.get_environment("WEFT_GODOT_MODE")
	out_path = OS.get_environment("WEFT_GODOT_OUT")
	n_frames = int(OS.get_environment("WEFT_GODOT_FRAMES"))
	# mode: [scene, cloth node, body node, the node turning it]
	var scenes = {"skirt": ["skirt.tscn", "Skirt", "Body/BodyMesh", "Body"],
		"skinned": ["skinned_skirt.tscn", "Skirt", "Body/Skeleton/BodyMesh", "Body/Skeleton"],
		"bend": ["bend.tscn", "Cloth", "", ""]}
	var s = scenes.get(mode, ["flag.tscn", "Flag", "", ""])
	var scene = load("res://" + s[0]).instance()
	flag = scene.get_node(s[1])
	rest = flag.mesh.surface_get_arrays(0)
	if s[2] != "":
		var b = scene.get_node(s[2])
		body = {"transform": _transform_list(b.transform), "rest": _vec_list(b.mesh.surface_get_arrays(0)[Mesh.ARRAY_VERTEX]),
			"indices": Array(b.mesh.surface_get_arrays(0)[Mesh.ARRAY_INDEX]),
			"degrees_per_second": scene.get_node(s[3]).degrees_per_second}
	if mode == "scaled":
		_scale_colliders(scene)
	if mode == "surfaces":
		pinned = Array(flag.pinned_vertices)
		_split_surfaces(flag)
		for k in range(flag.mesh.get_surface_count()):
			flag_rest_surfaces.append(flag.mesh.surface_get_arrays(k)[Mesh.ARRAY_VERTEX])
	if mode == "broken":
		flag.stiffness_stretch = NAN   # refused: stays 4000
		flag.colliders_root = NodePath("NoSuchNode")
		var lost = MeshInstance.new()
		lost.name = "Lost"
		lost.mesh = load("res://no_such_mesh.tres")   # Godot: cannot load; the mesh stays null
		lost.set_script(load("res://weft_cloth.gdns"))
		scene.add_child(lost)
		broken.append(lost)
		var sk = Skeleton.new()
		sk.name = "Skeleton"
		sk.add_bone("hips")
		scene.add_child(sk)
		# skinned bodies that are wrong: a vertex weighted to a bind the skin lacks, a bind naming
		# no bone
		var skin = Skin.new()
		skin.add_bind(0, Transform())
		skin.set_bind_name(0, "no_such_bone")
		for body_name in ["BadBindBody", "BadBoneNameBody"]:
			var arrays = []
			arrays.resize(Mesh.ARRAY_MAX)
			arrays[Mesh.ARRAY_VERTEX] = PoolVector3Array([Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 0, 1)])
			arrays[Mesh.ARRAY_BONES] = PoolIntArray([0, 0, 0, 0, 0, 0, 0, 0, 3 if body_name == "BadBindBody" else 0, 0, 0, 0])
			arrays[Mesh.ARRAY_WEIGHTS] = PoolRealArray([1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0])
			var b = MeshInstance.new()
			b.name = body_name
			b.mesh = ArrayMesh.new()
			b.mesh.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
			b.skeleton = NodePath("../Skeleton")
			if body_name == "BadBoneNameBody":
				b.skin = skin
			scene.add_child(b)
		# a cloth whose mesh has a surface of lines after one of triangles: refused
		var lines = ArrayMesh.new()
		for primitive in [Mesh.PRIMITIVE_TRIANGLES, Mesh.PRIMITIVE_LINES]:
			var arrays = []
			arrays.resize(Mesh.ARRAY_MAX)
			arrays[Mesh.ARRAY_VERTEX] = PoolVector3Array([Vector3(0, 1, 0), Vector3(1, 1, 0), Vector3(0, 1, 1), Vector3(1, 1, 1)])
			lines.add_surface_from_arrays(primitive, arrays)
		var lined = MeshInstance.new()
		lined.name = "Lines"
		lined.mesh = lines
		lined.set_script(load("res://weft_cloth.gdns"))
		scene.add_child(lined)
		broken.append(lined)
		# name: [attach_skeleton, attach_bones, attach_vertices, body]
		var bad = {"NoSkeleton": ["NoSuchSkeleton", ["hips"], [PoolIntArray([0])], ""],
			"NotSkeleton": ["../Ball", ["hips"], [PoolIntArray([0])], ""],
			"NoBone": ["../Skeleton", ["nope"], [PoolIntArray([0])], ""],
			"Mismatch": ["../Skeleton", ["hips"], [], ""],
			"NotVertices": ["../Skeleton", ["hips"], ["zero"], ""],
			"NoBody": ["", [], [], "NoSuchBody"],
			"NotBody": ["", [], [], "../Ball"],
			"BadBind": ["", [], [], "../BadBindBody"],
			"BadBoneName": ["", [], [], "../BadBoneNameBody"]}
		for name in bad:
			var m = MeshInstance.new()
			m.name = name
			m.mesh = PlaneMesh.new()
			m.set_script(load("res://weft_cloth.gdns"))
			m.attach_skeleton = NodePath(bad[name][0])
			m.attach_bones = PoolStringArray(bad[name][1])
			m.attach_vertices = bad[name][2]
			m.body = NodePath(bad[name][3])
			scene.add_child(m)
			broken.append(m)
	root.add_child(scene)

# The flag's mesh as two surfaces (its triangles left and right of its middle, each with its own
# vertices: the middle column twice) with materials "left" and "right"; its pins renumbered.
func _split_surfaces(flag):
	var a = flag.mesh.surface_get_arrays(0)
	var verts = a[Mesh.ARRAY_VERTEX]
	var idx = a[Mesh.ARRAY_INDEX]
	var mesh = ArrayMesh.new()
	var joined = {}   # flag vertex -> its index in the two surfaces joined (the last side's)
	var first = 0
	for side in [0, 1]:
		var local = {}
		var v = PoolVector3Array()
		var ix = PoolIntArray()
		for t in range(0, idx.size(), 3):
			var cx = (verts[idx[t]].x + verts[idx[t + 1]].x + verts[idx[t + 2]].x) / 3
			if (cx < 0) != (side == 0):
				continue
			for j in range(3):
				var o = idx[t + j]
				if not local.has(o):
					local[o] = v.size()
					v.append(verts[o])
				ix.append(local[o])
		var arrays = []
		arrays.resize(Mesh.ARRAY_MAX)
		arrays[Mesh.ARRAY_VERTEX] = v
		arrays[Mesh.ARRAY_INDEX] = ix
		mesh.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
		var m = SpatialMaterial.new()
		m.resource_name = "left" if side == 0 else "right"
		mesh.surface_set_material(side, m)
		for o in local:
			joined[o] = first + local[o]
		first += v.size()
	flag.mesh = mesh
	var pins = PoolIntArray()
	for p in flag.pinned_vertices:
		pins.append(joined[p])
	flag.pinned_vertices = pins

# flag.tscn with scaled colliders: the ball (radius 0.2) in a body scaled 1.5, a capsule in a
# body turned and scaled 1.25 (along the flag's pinned edge, beyond the ball), the ground plane (its normal tilted in its own frame) in a body
# turned, then scaled non-uniformly, and a sphere scaled non-uniformly (refused) where the flag
# falls
func _scale_colliders(scene):
	scene.get_node("Ball").scale = Vector3(1.5, 1.5, 1.5)
	scene.get_node("Ball/Shape").shape.radius = 0.2
	var bar = CapsuleShape.new()
	bar.radius = 0.06
	bar.height = 0.8
	var xf = Transform(Basis(Vector3(0, 1, 0), deg2rad(-30)).scaled(Vector3(1.25, 1.25, 1.25)), Vector3(-0.26, 1.25, -0.15))
	_static_shape(scene, "Bar", xf, bar)
	var ground = scene.get_node("Ground/Shape")
	ground.shape = PlaneShape.new()
	ground.shape.plane = Plane(Vector3(0.3, 1, 0.2).normalized(), 0.2)
	var squash = Basis(Vector3(2, 0, 0), Vector3(0, 0.5, 0), Vector3(0, 0, 1))
	scene.get_node("Ground").transform = Transform(squash * Basis(Vector3(0, 0, 1), deg2rad(25)), Vector3(0, 0.75, 0))
	var egg = SphereShape.new()
	egg.radius = 0.15
	_static_shape(scene, "Squashed", Transform(squash, Vector3(-0.3, 1.3, 0)), egg)

func _static_shape(scene, name, xf, shape):
	var body = StaticBody.new()
	body.name = name
	body.transform = xf
	var cs = CollisionShape.new()
	cs.name = "Shape"
	cs.shape = shape
	body.add_child(cs)
	scene.add_child(body)

# Every CollisionShape under the scene: its shape's sizes and its global transform.
func _colliders(scene):
	var l = []
	for body in scene.get_children():
		var cs = body.get_node_or_null("Shape")
		if cs == null:
			continue
		var c = {"name": body.name, "transform": _transform_list(cs.global_transform)}
		if cs.shape is SphereShape:
			c["sphere"] = cs.shape.radius
		elif cs.shape is CapsuleShape:
			c["capsule"] = [cs.shape.radius, cs.shape.height]
		elif cs.shape is PlaneShape:
			c["plane"] = [cs.shape.plane.x, cs.shape.plane.y, cs.shape.plane.z, cs.shape.plane.d]
		l.append(c)
	return l

func _transform_list(t):
	return [t.basis.x.x, t.basis.x.y, t.basis.x.z, 0, t.basis.y.x, t.basis.y.y, t.basis.y.z, 0,
		t.basis.z.x, t.basis.z.y, t.basis.z.z, 0, t.origin.x, t.origin.y, t.origin.z, 1]

func _vec_list(a):
	var l = []
	for v in a:
		l.append(v.x)
		l.append(v.y)
		l.append(v.z)
	return l

func _iteration(delta):   # before the nodes' _physics_process
	ticks += 1
	var stepped = flag.get_frames() if flag.has_method("get_frames") else -1
	if stepped < n_frames and ticks < n_frames + 10:
		return
	var d = {"frames": stepped, "dt": delta, "simulating": flag.is_simulating()}
	if mode == "bend":
		d["body_vertices"] = _vec_list(flag.get_body_vertices())
	elif mode != "broken":
		d["transform"] = _transform_list(flag.global_transform)
		d["rest"] = _vec_list(rest[Mesh.ARRAY_VERTEX])
		d["indices"] = Array(rest[Mesh.ARRAY_INDEX])
		d["positions"] = _vec_list(flag.mesh.surface_get_arrays(0)[Mesh.ARRAY_VERTEX])
		d["pinned"] = Array(flag.pinned_vertices) if pinned == null else pinned
		if mode == "surfaces":   # each surface's rest and simulated vertices, and material
			d["joined_pinned"] = Array(flag.pinned_vertices)
			d["surfaces"] = []
			for k in range(flag.mesh.get_surface_count()):
				var m = flag.mesh.surface_get_material(k)
				d["surfaces"].append({"material": m.resource_name if m != null else "",
					"rest": _vec_list(flag_rest_surfaces[k]),
					"indices": Array(flag.mesh.surface_get_arrays(k)[Mesh.ARRAY_INDEX]),
					"positions": _vec_list(flag.mesh.surface_get_arrays(k)[Mesh.ARRAY_VERTEX])})
		var material = {}
		for k in ["density", "stiffness_stretch", "stiffness_shear", "stiffness_bend", "damping_stretch",
				"damping_shear", "damping_bend", "substeps", "max_iterations", "tolerance",
				"collider_thickness", "collider_friction"]:
			material[k] = flag.get(k)
		d["settings"] = material
		if mode == "scaled":
			d["colliders"] = _colliders(flag.get_parent())
		if mode == "flag" or mode == "surfaces":
			var ball = flag.get_node("../Ball/Shape")
			d["ball"] = {"center": [ball.global_transform.origin.x, ball.global_transform.origin.y,
				ball.global_transform.origin.z], "radius": ball.shape.radius}
		elif body != null:
			d["attached"] = Array(flag.attach_vertices[0])
			d["body"] = body
	else:
		d["stiffness_stretch"] = flag.stiffness_stretch
		d["lost_simulating"] = broken[0].is_simulating()
		for m in broken:
			d[m.name + "_simulating"] = m.is_simulating()
	var f = File.new()
	f.open(out_path, File.WRITE)
	f.store_string(to_json(d))
	f.close()
	quit()
	return true
