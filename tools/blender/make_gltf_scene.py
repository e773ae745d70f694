"""Builds the glTF scene data/scenes/props.glb in code (no .blend file): Suzanne, a torus, an
icosphere and a box on a plinth textured with a generated colour-grid image, metallic-roughness
materials (matte, glossy, metal) and a camera.
data/scenes/props.json adds lights and a camera path around it (a glTF has no lights we read).

    blender -b --factory-startup -P tools/blender/make_gltf_scene.py -- --output data/scenes/props.glb
"""
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
output = args[args.index("--output") + 1] if "--output" in args else "props.glb"

bpy.ops.wm.read_factory_settings(use_empty=True)


def material(name, color, metallic, roughness, image=None):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    if image is not None:
        tex = m.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = image
        m.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return m


grid = bpy.data.images.new("grid", 256, 256)
grid.generated_type = "COLOR_GRID"
grid.pack()
grid.filepath_raw = "//grid.png"
grid.file_format = "PNG"

plinth_mat = material("plinth", (0.6, 0.6, 0.6), 0.0, 0.7, grid)
objects = [
    (bpy.ops.mesh.primitive_monkey_add, {"size": 1.2, "location": (-1.3, 0.0, 0.75)}, material("suzanne", (0.8, 0.35, 0.1), 0.0, 0.35)),
    (bpy.ops.mesh.primitive_torus_add, {"major_radius": 0.55, "minor_radius": 0.18, "location": (0.2, -0.3, 0.6), "rotation": (1.2, 0, 0.4)},
     material("gold", (1.0, 0.78, 0.34), 1.0, 0.2)),
    (bpy.ops.mesh.primitive_ico_sphere_add, {"radius": 0.45, "subdivisions": 3, "location": (1.3, 0.4, 0.45)},
     material("steel", (0.9, 0.9, 0.92), 1.0, 0.05)),
    (bpy.ops.mesh.primitive_cube_add, {"size": 0.6, "location": (0.4, 1.1, 0.3), "rotation": (0, 0, 0.6)},
     material("blue", (0.1, 0.3, 0.8), 0.0, 0.5)),
    (bpy.ops.mesh.primitive_cylinder_add, {"radius": 2.6, "depth": 0.1, "location": (0, 0, -0.05)}, plinth_mat),
]
for op, kwargs, mat in objects:
    op(**kwargs)
    obj = bpy.context.active_object
    obj.data.materials.append(mat)
    if op is bpy.ops.mesh.primitive_monkey_add:
        mod = obj.modifiers.new("subdivision", "SUBSURF")
        mod.levels = 1
        bpy.ops.object.shade_smooth()
    if op is bpy.ops.mesh.primitive_cylinder_add:
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.uv.cylinder_project()
        bpy.ops.object.mode_set(mode="OBJECT")

bpy.ops.object.camera_add(location=(0.0, -5.5, 2.4), rotation=(1.22, 0.0, 0.0))
bpy.context.scene.camera = bpy.context.active_object

bpy.ops.export_scene.gltf(filepath=output, export_format="GLB", export_apply=True, export_cameras=True,
                          export_lights=False, export_yup=True)
print(f"wrote {output}")
