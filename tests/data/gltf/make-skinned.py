# Makes the skinned test characters: a closed body (metaballs turned into a mesh), an
# armature, weights from Blender's automatic weights (bone heat), and clips, exported by
# Blender's glTF exporter. Run:
#   blender --background --factory-startup --python make-skinned.py -- OUT.glb KIND
# KIND: `figure` (Blender metarig bone names), `mixamo` (the figure as Mixamo characters
# come into Blender: `mixamorig:` names, modelled in centimetres under an armature scaled
# by 0.01), `dog` (a quadruped with a neck and a tail).
import sys
import math
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Blender 3.x's exporter uses the alias newer numpy removed
import bpy
from mathutils import Vector, Quaternion

args = sys.argv[sys.argv.index("--") + 1:]
out = args[0]
kind = args[1] if len(args) > 1 else "figure"
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
# Mixamo's characters are modelled in centimetres.
unit = 100.0 if kind == "mixamo" else 1.0

# The body: capsules and balls of one metaball object (Blender is z-up; the glTF is y-up).
mball = bpy.data.metaballs.new("body")
mball.resolution = 0.03 * unit
mball.render_resolution = 0.03 * unit
body = bpy.data.objects.new("body", mball)
scene.collection.objects.link(body)


def v(p):
    return Vector(p) * unit


def capsule(a, b, radius):
    a, b = v(a), v(b)
    e = mball.elements.new(type="CAPSULE")
    e.co = (a + b) / 2
    e.radius = radius * unit
    e.size_x = (b - a).length / 2
    e.rotation = Vector((1, 0, 0)).rotation_difference((b - a).normalized())


def ball(c, radius):
    e = mball.elements.new(type="BALL")
    e.co = v(c)
    e.radius = radius * unit


if kind == "dog":
    capsule((0, -0.30, 0.55), (0, 0.30, 0.55), 0.15)          # trunk, head toward -y
    capsule((0, -0.32, 0.58), (0, -0.45, 0.78), 0.07)         # neck
    ball((0, -0.50, 0.84), 0.10)                              # head
    capsule((0, -0.52, 0.82), (0, -0.66, 0.78), 0.05)         # snout
    capsule((0, 0.32, 0.60), (0, 0.62, 0.72), 0.035)          # tail
    for s in (1, -1):
        for y in (-0.24, 0.24):                               # front and hind legs
            capsule((s * 0.09, y, 0.50), (s * 0.09, y, 0.06), 0.05)
            capsule((s * 0.09, y, 0.05), (s * 0.09, y - 0.08, 0.04), 0.045)
else:
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
character = bpy.context.view_layer.objects.active
character.name = kind

arm_data = bpy.data.armatures.new("rig")
rig = bpy.data.objects.new("rig", arm_data)
scene.collection.objects.link(rig)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.mode_set(mode="EDIT")
bones = {}


def bone(name, head, tail, parent=None, connect=False):
    b = arm_data.edit_bones.new(name)
    b.head, b.tail = v(head), v(tail)
    if parent:
        b.parent = bones[parent]
        b.use_connect = connect
    bones[name] = b


# The figure's bones with the names each rig gives them.
METARIG = {
    "hips": "spine", "spine": "spine.001", "neck": "neck", "head": "head",
    "arm": "upper_arm.{s}", "forearm": "forearm.{s}", "hand": "hand.{s}",
    "leg": "thigh.{s}", "shin": "shin.{s}", "foot": "foot.{s}",
}
MIXAMO = {
    "hips": "mixamorig:Hips", "spine": "mixamorig:Spine", "neck": "mixamorig:Neck",
    "head": "mixamorig:Head", "arm": "mixamorig:{side}Arm",
    "forearm": "mixamorig:{side}ForeArm", "hand": "mixamorig:{side}Hand",
    "leg": "mixamorig:{side}UpLeg", "shin": "mixamorig:{side}Leg",
    "foot": "mixamorig:{side}Foot",
}
names = MIXAMO if kind == "mixamo" else METARIG


def name(part, s=""):
    return names[part].format(s=s, side={"L": "Left", "R": "Right", "": ""}[s])


if kind == "dog":
    bone("spine", (0, 0.28, 0.55), (0, 0.0, 0.55))
    bone("spine.001", (0, 0.0, 0.55), (0, -0.30, 0.57), "spine", True)
    bone("neck", (0, -0.30, 0.57), (0, -0.46, 0.78), "spine.001", True)
    bone("head", (0, -0.46, 0.78), (0, -0.66, 0.80), "neck", True)
    bone("tail", (0, 0.32, 0.60), (0, 0.47, 0.66), "spine")
    bone("tail.001", (0, 0.47, 0.66), (0, 0.64, 0.73), "tail", True)
    for s, side in ((1, "L"), (-1, "R")):
        for front, y, parent in ((True, -0.24, "spine.001"), (False, 0.24, "spine")):
            top, mid, low = (("upper_arm", "forearm", "hand") if front
                             else ("thigh", "shin", "foot"))
            bone(f"{top}.{side}", (s * 0.09, y, 0.50), (s * 0.09, y, 0.28), parent)
            bone(f"{mid}.{side}", (s * 0.09, y, 0.28), (s * 0.09, y, 0.06), f"{top}.{side}", True)
            bone(f"{low}.{side}", (s * 0.09, y, 0.06), (s * 0.09, y - 0.10, 0.03), f"{mid}.{side}", True)
else:
    bone(name("hips"), (0, 0, 0.92), (0, 0, 1.15))
    bone(name("spine"), (0, 0, 1.15), (0, 0, 1.42), name("hips"), True)
    bone(name("neck"), (0, 0, 1.42), (0, 0, 1.56), name("spine"), True)
    bone(name("head"), (0, 0, 1.56), (0, 0, 1.84), name("neck"), True)
    for s, side in ((1, "L"), (-1, "R")):
        bone(name("arm", side), (s * 0.20, 0, 1.40), (s * 0.48, 0, 1.40), name("spine"))
        bone(name("forearm", side), (s * 0.48, 0, 1.40), (s * 0.76, 0, 1.40), name("arm", side), True)
        bone(name("hand", side), (s * 0.76, 0, 1.40), (s * 0.92, 0, 1.40), name("forearm", side), True)
        bone(name("leg", side), (s * 0.11, 0, 0.92), (s * 0.11, 0, 0.50), name("hips"))
        bone(name("shin", side), (s * 0.11, 0, 0.50), (s * 0.11, 0, 0.08), name("leg", side), True)
        bone(name("foot", side), (s * 0.11, 0, 0.08), (s * 0.11, -0.20, 0.05), name("shin", side), True)
bpy.ops.object.mode_set(mode="OBJECT")

# Automatic weights (bone heat).
bpy.ops.object.select_all(action="DESELECT")
character.select_set(True)
rig.select_set(True)
bpy.context.view_layer.objects.active = rig
bpy.ops.object.parent_set(type="ARMATURE_AUTO")
if kind == "mixamo":
    # Centimetres under an armature scaled to metres, as Mixamo's FBX comes in.
    rig.scale = (0.01, 0.01, 0.01)


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
if kind == "dog":
    def legs(a):
        return {"upper_arm.L": ((1, 0, 0), a), "thigh.R": ((1, 0, 0), a),
                "upper_arm.R": ((1, 0, 0), -a), "thigh.L": ((1, 0, 0), -a),
                "forearm.L": ((1, 0, 0), -abs(a) / 2), "shin.R": ((1, 0, 0), abs(a) / 2)}
    key("trot", [(1, {}), (9, legs(30)), (17, legs(-30)), (25, {})])
    key("wag", [(1, {}), (7, {"tail": ((0, 0, 1), 35), "tail.001": ((0, 0, 1), 25)}),
                (13, {"tail": ((0, 0, 1), -35), "tail.001": ((0, 0, 1), -25)}),
                (19, {"tail": ((0, 0, 1), 35)}), (25, {})])
    # Ends away from rest: the head turned and held.
    key("look", [(1, {}), (25, {"neck": ((0, 0, 1), 40), "head": ((1, 0, 0), 20)})])
else:
    key("raise", [
        (1, {}),
        (25, {name("arm", "R"): ((0, 0, 1), 70), name("forearm", "R"): ((0, 0, 1), 30)}),
    ])
    key("walk", [
        (1, {}),
        (13, {name("leg", "L"): ((1, 0, 0), 30), name("leg", "R"): ((1, 0, 0), -30),
              name("shin", "L"): ((1, 0, 0), -20), name("arm", "L"): ((0, 0, 1), -25),
              name("arm", "R"): ((0, 0, 1), 25), name("head"): ((1, 0, 0), 15)}),
        (25, {name("leg", "L"): ((1, 0, 0), -30), name("leg", "R"): ((1, 0, 0), 30),
              name("shin", "R"): ((1, 0, 0), -20), name("arm", "L"): ((0, 0, 1), 25),
              name("arm", "R"): ((0, 0, 1), -25), name("head"): ((1, 0, 0), -15)}),
        (37, {}),
    ])
    key("wave", [
        (1, {}),
        (13, {name("arm", "R"): ((0, 0, 1), 60), name("forearm", "R"): ((0, 0, 1), 45),
              name("hand", "R"): ((1, 0, 0), 30)}),
        (25, {name("arm", "R"): ((0, 0, 1), 60), name("forearm", "R"): ((0, 0, 1), 80),
              name("hand", "R"): ((1, 0, 0), -30)}),
        (37, {}),
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
