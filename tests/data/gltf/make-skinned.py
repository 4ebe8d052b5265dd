# Makes `skinned-figure.glb`: a closed figure (metaballs turned into a mesh), an armature
# with the bone names Blender's metarig uses, weights from Blender's automatic weights
# (bone heat), and three clips. Run: blender --background --python make-skinned.py -- OUT.glb
import sys
import math
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool
import bpy
from mathutils import Vector, Quaternion

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# The body: capsules and balls of one metaball object (Blender is z-up; the glTF is y-up).
mball = bpy.data.metaballs.new("body")
mball.resolution = 0.03
mball.render_resolution = 0.03
body = bpy.data.objects.new("body", mball)
scene.collection.objects.link(body)


def capsule(a, b, radius):
    a, b = Vector(a), Vector(b)
    e = mball.elements.new(type="CAPSULE")
    e.co = (a + b) / 2
    e.radius = radius
    e.size_x = (b - a).length / 2
    e.rotation = Vector((1, 0, 0)).rotation_difference((b - a).normalized())


def ball(c, radius):
    e = mball.elements.new(type="BALL")
    e.co = c
    e.radius = radius


capsule((0, 0, 0.95), (0, 0, 1.40), 0.19)      # trunk
capsule((0, 0, 1.40), (0, 0, 1.55), 0.07)      # neck
ball((0, 0, 1.68), 0.14)                       # head
for s in (1, -1):
    capsule((s * 0.18, 0, 1.40), (s * 0.80, 0, 1.40), 0.06)   # arm
    ball((s * 0.84, 0, 1.40), 0.07)                          # hand
    capsule((s * 0.11, 0, 0.92), (s * 0.11, 0, 0.10), 0.075) # leg
    capsule((s * 0.11, 0.0, 0.09), (s * 0.11, -0.16, 0.07), 0.065)  # foot

bpy.context.view_layer.objects.active = body
body.select_set(True)
bpy.ops.object.convert(target="MESH")
figure = bpy.context.view_layer.objects.active
figure.name = "figure"

# The armature: metarig names.
arm_data = bpy.data.armatures.new("rig")
rig = bpy.data.objects.new("rig", arm_data)
scene.collection.objects.link(rig)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.mode_set(mode="EDIT")
bones = {}


def bone(name, head, tail, parent=None, connect=False):
    b = arm_data.edit_bones.new(name)
    b.head, b.tail = head, tail
    if parent:
        b.parent = bones[parent]
        b.use_connect = connect
    bones[name] = b


bone("spine", (0, 0, 0.92), (0, 0, 1.15))
bone("spine.001", (0, 0, 1.15), (0, 0, 1.42), "spine", True)
bone("neck", (0, 0, 1.42), (0, 0, 1.56), "spine.001", True)
bone("head", (0, 0, 1.56), (0, 0, 1.84), "neck", True)
for s, side in ((1, "L"), (-1, "R")):
    bone(f"upper_arm.{side}", (s * 0.20, 0, 1.40), (s * 0.48, 0, 1.40), "spine.001")
    bone(f"forearm.{side}", (s * 0.48, 0, 1.40), (s * 0.76, 0, 1.40), f"upper_arm.{side}", True)
    bone(f"hand.{side}", (s * 0.76, 0, 1.40), (s * 0.92, 0, 1.40), f"forearm.{side}", True)
    bone(f"thigh.{side}", (s * 0.11, 0, 0.92), (s * 0.11, 0, 0.50), "spine")
    bone(f"shin.{side}", (s * 0.11, 0, 0.50), (s * 0.11, 0, 0.08), f"thigh.{side}", True)
    bone(f"foot.{side}", (s * 0.11, 0, 0.08), (s * 0.11, -0.20, 0.05), f"shin.{side}", True)
bpy.ops.object.mode_set(mode="OBJECT")

# Automatic weights (bone heat).
bpy.ops.object.select_all(action="DESELECT")
figure.select_set(True)
rig.select_set(True)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.parent_set(type="ARMATURE_AUTO")


def key(action_name, frames):
    """An action: at each frame, the bones' rotations (axis in bone space, degrees)."""
    action = bpy.data.actions.new(action_name)
    rig.animation_data_create()
    rig.animation_data.action = action
    for frame, turns in frames:
        for pb in rig.pose.bones:
            pb.rotation_mode = "QUATERNION"
            axis, degrees = turns.get(pb.name, ((1, 0, 0), 0))
            pb.rotation_quaternion = Quaternion(Vector(axis), math.radians(degrees))
            pb.keyframe_insert("rotation_quaternion", frame=frame)
    track = rig.animation_data.nla_tracks.new()
    track.name = action_name
    track.strips.new(action_name, 1, action)
    rig.animation_data.action = None


# Bone space: y along the bone; x and z across it.
key("walk", [
    (1, {}),
    (13, {"thigh.L": ((1, 0, 0), 30), "thigh.R": ((1, 0, 0), -30),
          "shin.L": ((1, 0, 0), -20), "upper_arm.L": ((0, 0, 1), -25),
          "upper_arm.R": ((0, 0, 1), 25), "head": ((1, 0, 0), 15)}),
    (25, {"thigh.L": ((1, 0, 0), -30), "thigh.R": ((1, 0, 0), 30),
          "shin.R": ((1, 0, 0), -20), "upper_arm.L": ((0, 0, 1), 25),
          "upper_arm.R": ((0, 0, 1), -25), "head": ((1, 0, 0), -15)}),
    (37, {}),
])
key("wave", [
    (1, {}),
    (13, {"upper_arm.R": ((0, 0, 1), 60), "forearm.R": ((0, 0, 1), 45),
          "hand.R": ((1, 0, 0), 30)}),
    (25, {"upper_arm.R": ((0, 0, 1), 60), "forearm.R": ((0, 0, 1), 80),
          "hand.R": ((1, 0, 0), -30)}),
    (37, {}),
])
# A clip that ends away from rest: the right arm raised and held.
key("raise", [
    (1, {}),
    (25, {"upper_arm.R": ((0, 0, 1), 70), "forearm.R": ((0, 0, 1), 30)}),
])
for pb in rig.pose.bones:
    pb.rotation_quaternion = Quaternion()
scene.frame_set(1)

bpy.ops.export_scene.gltf(
    filepath=out,
    export_format="GLB",
    export_animations=True,
    export_nla_strips=True,
    export_skins=True,
    export_morph=False,
    export_normals=True,
    export_texcoords=False,
    export_materials="NONE",
)
