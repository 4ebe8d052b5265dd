# Reads a take (.glb) with Blender's glTF importer and writes the mesh as Blender shows it
# at some frames, in glTF's axes: blender --background --python blender-take.py -- TAKE.glb
# OUT.json FRAME...
import sys
import json
import numpy
if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Blender 3.x's importer uses the alias newer numpy removed
import bpy

args = sys.argv[sys.argv.index("--") + 1:]
take, out, frames = args[0], args[1], [int(f) for f in args[2:]]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=take)
obj = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
scene = bpy.context.scene
shown = {"fps": scene.render.fps / scene.render.fps_base}
for f in frames:
    scene.frame_set(f)
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    # Blender is z-up: glTF's (x, y, z) is Blender's (x, z, -y).
    shown[str(f)] = [[v.co.x, v.co.z, -v.co.y] for v in mesh.vertices]
json.dump(shown, open(out, "w"))
