# On a Skeleton: turns the bone named `bone` about `axis` (in the bone's frame) at
# degrees_per_second, from the first physics frame (its pose; the rest stays), as an animation
# would.
extends Skeleton

export var bone = "hips"
export var axis = Vector3.UP
export var degrees_per_second = 180.0
var seconds = 0.0

func _physics_process(delta):
	seconds += delta
	set_bone_pose(find_bone(bone), Transform(Basis(axis.normalized(), deg2rad(degrees_per_second * seconds))))
