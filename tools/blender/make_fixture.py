"""Build a tiny Cycles scene from scratch and render a multilayer-EXR fixture.

Run (Blender 3.4, Debian package `blender`):

    blender -b --factory-startup -P tools/blender/make_fixture.py -- \
        --output tests/fixtures/blender

Writes <output>/frame_0001.exr .. frame_0005.exr (OPEN_EXR_MULTILAYER, 32-bit
float, ZIP) and <output>/cameras.json (per-frame camera and object matrices).
Nothing is loaded from a .blend file; everything is built below.
"""

import argparse
import json
import math
import os
import re
import sys

import bpy
from mathutils import Euler, Vector

WIDTH, HEIGHT = 64, 36
FRAME_START, FRAME_END = 1, 5
# Matrices are also exported for these neighbours so that the backward
# (Vector.XY) and forward (Vector.ZW) motion of every rendered frame can be
# checked, including frames 1 and 5.
EXPORT_FRAMES = list(range(FRAME_START - 1, FRAME_END + 2))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_fixture.py")
    p.add_argument("--output", required=True, help="output directory")
    p.add_argument("--filter-width", type=float, default=None,
                   help="Cycles pixel filter width in pixels (default: Blender's 1.5)")
    p.add_argument("--frames", type=int, default=FRAME_END,
                   help="last frame to render (default 5)")
    return p.parse_args(argv)


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras,
                 bpy.data.lights, bpy.data.images):
        for block in list(coll):
            coll.remove(block)


def diffuse_material(name, color, checker=None):
    """Pure diffuse material; `checker` = (color2, scale) adds a checker texture."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    if checker is not None:
        color2, scale = checker
        tex = nt.nodes.new("ShaderNodeTexChecker")
        tex.inputs["Color1"].default_value = (*color, 1.0)
        tex.inputs["Color2"].default_value = (*color2, 1.0)
        tex.inputs["Scale"].default_value = scale
        coord = nt.nodes.new("ShaderNodeTexCoord")
        nt.links.new(coord.outputs["Object"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bsdf.inputs["Color"])
    return mat


def add(op, name, material, pass_index, **kwargs):
    op(**kwargs)
    obj = bpy.context.active_object
    obj.name = name
    obj.pass_index = pass_index
    obj.data.materials.append(material)
    return obj


def set_linear(obj):
    if obj.animation_data and obj.animation_data.action:
        for fc in obj.animation_data.action.fcurves:
            fc.extrapolation = "LINEAR"
            for kp in fc.keyframe_points:
                kp.interpolation = "LINEAR"


def build_scene():
    scene = bpy.context.scene

    # World: dim uniform grey so shadows are not black.
    world = bpy.data.worlds.new("World") if scene.world is None else scene.world
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0.05, 0.06, 0.08, 1.0)
    bg.inputs["Strength"].default_value = 1.0

    floor = add(bpy.ops.mesh.primitive_plane_add, "Floor",
                diffuse_material("FloorMat", (0.60, 0.60, 0.55),
                                 checker=((0.15, 0.15, 0.15), 1.0)),
                4, size=16.0, location=(0.0, 2.0, 0.0))
    # Back wall, 16 wide and 3 high: the sky is visible above it (background pixels).
    wall = add(bpy.ops.mesh.primitive_plane_add, "Wall",
               diffuse_material("WallMat", (0.35, 0.45, 0.70)),
               5, size=16.0, location=(0.0, 6.0, 1.5), rotation=(math.pi / 2, 0.0, 0.0))
    wall.scale = (1.0, 3.0 / 16.0, 1.0)

    cube = add(bpy.ops.mesh.primitive_cube_add, "Cube",
               diffuse_material("CubeMat", (0.80, 0.15, 0.10),
                                checker=((0.95, 0.85, 0.20), 2.0)),
               1, size=1.6, location=(-2.2, 2.0, 0.8), rotation=(0.0, 0.0, math.radians(30)))
    sphere = add(bpy.ops.mesh.primitive_uv_sphere_add, "Sphere",
                 diffuse_material("SphereMat", (0.10, 0.70, 0.20)),
                 2, radius=0.8, segments=32, ring_count=16, location=(-0.6, 0.5, 0.8))
    bpy.ops.object.shade_smooth()
    cyl = add(bpy.ops.mesh.primitive_cylinder_add, "Cylinder",
              diffuse_material("CylMat", (0.90, 0.90, 0.90)),
              3, radius=0.6, depth=2.4, vertices=24, location=(2.3, 2.8, 1.2))

    # Moving object: the sphere translates to the right (and a little up/back).
    # Keys at 0, 3, 6 with linear interpolation: the velocity changes at frame 3.
    for f, loc in ((0, (-1.4, 0.5, 0.8)), (3, (0.1, 0.5, 0.8)), (6, (1.3, 0.9, 1.1))):
        sphere.location = loc
        sphere.keyframe_insert("location", frame=f)
    set_linear(sphere)

    # Camera: translates and pans a little; velocity changes at frame 3.
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 35.0
    cam_data.sensor_fit = "AUTO"
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.rotation_mode = "XYZ"
    keys = (
        (0, (-0.8, -8.0, 2.6), (80.0, 0.0, -4.0)),
        (3, (0.0, -7.7, 2.5), (79.0, 0.0, 0.0)),
        (6, (0.5, -7.6, 2.55), (79.5, 1.0, 2.0)),
    )
    for f, loc, rot_deg in keys:
        cam.location = loc
        cam.rotation_euler = Euler([math.radians(a) for a in rot_deg], "XYZ")
        cam.keyframe_insert("location", frame=f)
        cam.keyframe_insert("rotation_euler", frame=f)
    set_linear(cam)

    # Lights: a sun for hard shadows plus an area light for soft fill.
    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(3.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = Euler((math.radians(50), math.radians(10), math.radians(35)), "XYZ")
    scene.collection.objects.link(sun)

    area_data = bpy.data.lights.new("Area", type="AREA")
    area_data.energy = 300.0
    area_data.size = 2.0
    area = bpy.data.objects.new("Area", area_data)
    area.location = (-3.0, -3.0, 5.0)
    area.rotation_euler = (Vector((0.0, 2.0, 0.5)) - area.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(area)

    return scene, cam, [floor, wall, cube, sphere, cyl]


def configure_render(scene, output, filter_width, last_frame):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.render.resolution_x = WIDTH
    scene.render.resolution_y = HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = 1.0
    scene.render.pixel_aspect_y = 1.0
    scene.render.use_motion_blur = False  # required for the Vector pass
    scene.render.use_border = False
    scene.render.film_transparent = False
    scene.frame_start = FRAME_START
    scene.frame_end = last_frame

    cy = scene.cycles
    cy.samples = 1
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.use_preview_denoising = False
    cy.use_animated_seed = True
    cy.seed = 0
    if filter_width is not None:
        cy.filter_width = filter_width

    vl = scene.view_layers[0]
    vl.name = "ViewLayer"
    vl.use_pass_combined = True
    vl.use_pass_normal = True
    vl.use_pass_vector = True
    vl.use_pass_z = True
    vl.use_pass_position = True
    vl.use_pass_object_index = True
    vl.use_pass_diffuse_color = True
    vl.cycles.denoising_store_passes = True

    img = scene.render.image_settings
    img.file_format = "OPEN_EXR_MULTILAYER"
    img.color_depth = "32"
    img.exr_codec = "ZIP"
    scene.render.use_file_extension = True
    scene.render.filepath = os.path.join(output, "frame_####")


def rowmajor(m):
    return [[float(m[r][c]) for c in range(4)] for r in range(4)]


def export_matrices(scene, cam, objects, output):
    frames = {}
    for f in EXPORT_FRAMES:
        scene.frame_set(f)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        cam_eval = cam.evaluated_get(depsgraph)
        frames[str(f)] = {
            "world_to_camera": rowmajor(cam_eval.matrix_world.inverted()),
            "camera_to_world": rowmajor(cam_eval.matrix_world),
            "projection": rowmajor(cam_eval.calc_matrix_camera(depsgraph, x=WIDTH, y=HEIGHT)),
            "objects": {
                o.name: rowmajor(o.evaluated_get(depsgraph).matrix_world) for o in objects
            },
        }
    scene.frame_set(FRAME_START)
    data = {
        "width": WIDTH,
        "height": HEIGHT,
        "frames": list(range(FRAME_START, scene.frame_end + 1)),
        "matrix_frames": EXPORT_FRAMES,
        "files": ["frame_%04d.exr" % f for f in range(FRAME_START, scene.frame_end + 1)],
        "cameras": frames,
        "camera": {"lens_mm": cam.data.lens, "sensor_width_mm": cam.data.sensor_width,
                   "sensor_fit": cam.data.sensor_fit, "clip_start": cam.data.clip_start,
                   "clip_end": cam.data.clip_end},
        "pass_index": {o.name: o.pass_index for o in objects},
        "moving_objects": ["Sphere"],
        "conventions": (
            "Matrices are row-major 4x4 (m[row][col]), Blender world space (Z up), "
            "column vectors: p_cam = world_to_camera @ [P,1]. Camera looks down -Z, +Y up. "
            "projection = camera.calc_matrix_camera(depsgraph, x=width, y=height) (OpenGL style): "
            "clip = projection @ p_cam, ndc = clip.xyz / clip.w in [-1,1] with +y up. "
            "Pixel coords with rows from the top (EXR order): px = (ndc.x + 1) / 2 * width, "
            "row = (1 - ndc.y) / 2 * height; pixel (i, j) has its centre at (i + 0.5, j + 0.5). "
            "Depth pass = -p_cam.z. 'objects' holds each object's matrix_world per frame. "
            "Matrices are given for frames in matrix_frames (rendered frames plus one on each side)."
        ),
        "render": {
            "blender": bpy.app.version_string,
            "engine": "CYCLES CPU",
            "samples": scene.cycles.samples,
            "use_animated_seed": scene.cycles.use_animated_seed,
            "filter_type": scene.cycles.pixel_filter_type,
            "filter_width": scene.cycles.filter_width,
            "motion_blur": scene.render.use_motion_blur,
            "view_layer": scene.view_layers[0].name,
        },
    }
    text = json.dumps(data, indent=1)
    # Put each list of numbers (matrix row, frame list) on one line.
    text = re.sub(r"\[\s*(-?[0-9][^\[\]{}\"]*?)\s*\]",
                  lambda m: "[" + ", ".join(v.strip() for v in m.group(1).split(",")) + "]",
                  text)
    with open(os.path.join(output, "cameras.json"), "w") as fh:
        fh.write(text + "\n")


def main():
    args = parse_args()
    output = os.path.abspath(args.output)
    os.makedirs(output, exist_ok=True)
    clear_scene()
    scene, cam, objects = build_scene()
    configure_render(scene, output, args.filter_width, args.frames)
    export_matrices(scene, cam, objects, output)
    bpy.ops.render.render(animation=True)


if __name__ == "__main__":
    main()
