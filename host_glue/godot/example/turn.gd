# Turns its node about the world's Y axis at degrees_per_second, from the first physics frame.
extends Spatial

export var degrees_per_second = 180.0
var seconds = 0.0

func _physics_process(delta):
	seconds += delta
	rotation = Vector3(0, deg2rad(degrees_per_second * seconds), 0)
