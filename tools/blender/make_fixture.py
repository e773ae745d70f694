"""Build a tiny Cycles scene from scratch and render a multilayer-EXR fixture.

Run (Blender 3.4, Debian package `blender`):

    blender -b --factory-startup -P tools/blender/make_fixture.py -- \
        --output tests/fixtures/blender

Writes <output>/frame_0001.exr .. frame_0005.exr (OPEN_EXR_MULTILAYER, 32-bit
float, ZIP) and <output>/cameras.json (per-frame camera and object matrices).
Nothing is loaded from a .blend file; everything is built below.

The glossy fixture (tests/fixtures/blender_glossy: reflections, light passes, references):

    blender -b --factory-startup -P tools/blender/make_fixture.py -- \
        --output tests/fixtures/blender_glossy --scene glossy --light-passes \
        --frames 8 --half --reference-samples 1024 --filter-width 0.01

(a pixel filter of 0.01 px puts every sample at the pixel centre, so the reference is the
expectation of the 1-spp frames, not an anti-aliased image) adds Cycles' light passes (DiffDir/DiffInd/DiffCol, GlossDir/GlossInd/GlossCol,
TransDir/TransInd/TransCol, Emit, Env) and renders <output>/reference/frame_NNNN.exr
(plain RGB EXR, `--reference-samples` samples, the same camera and scene).
"""

import argparse
import math
import os
import sys

import bpy
from mathutils import Euler, Vector

# The passes, render settings and camera matrices come from the set-up script users run on
# their own .blend, so the fixtures show what it produces.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rtdenoise_setup as setup  # noqa: E402

WIDTH, HEIGHT = 64, 36
FRAME_START, FRAME_END = 1, 5
# Matrices are also exported for the neighbours of the rendered frames (frame 0
# and the one after the last) so that the backward (Vector.XY) and forward
# (Vector.ZW) motion of every rendered frame can be checked.


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_fixture.py")
    p.add_argument("--output", required=True, help="output directory")
    p.add_argument("--filter-width", type=float, default=None,
                   help="Cycles pixel filter width in pixels (default: Blender's 1.5)")
    p.add_argument("--frames", type=int, default=FRAME_END,
                   help="last frame to render (default 5)")
    p.add_argument("--scene", choices=["diffuse", "glossy"], default="diffuse",
                   help="diffuse: the original fixture; glossy: a dark glossy floor, a wall mirror, "
                        "a glossy metal sphere and bright moving objects")
    p.add_argument("--light-passes", action="store_true",
                   help="also write the light passes (diffuse, glossy, transmission, emission, environment)")
    p.add_argument("--half", action="store_true", help="16-bit half float instead of 32-bit")
    p.add_argument("--size", default=None, help="WxH (default 64x36)")
    p.add_argument("--save-blend", default=None,
                   help="save the scene as built (before the rtdenoise set-up) to this .blend and stop: "
                        "the worked example of docs/blender.md")
    p.add_argument("--reference-samples", type=int, default=0,
                   help="also render <output>/reference/frame_NNNN.exr with this many samples")
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


def principled_material(name, color, roughness, metallic=0.0, specular=0.5):
    """Principled BSDF: roughness 0 with metallic 1 is a perfect mirror."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Specular"].default_value = specular
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


def build_glossy_scene():
    """A dark glossy floor reflecting brightly coloured objects (one moving), a mirror on the
    left wall, a glossy gold sphere; sun, area light and a dim sky; the camera slides right."""
    scene = bpy.context.scene
    world = bpy.data.worlds.new("World") if scene.world is None else scene.world
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0.20, 0.25, 0.35, 1.0)
    bg.inputs["Strength"].default_value = 1.0

    floor = add(bpy.ops.mesh.primitive_plane_add, "Floor",
                principled_material("FloorMat", (0.03, 0.03, 0.035), roughness=0.15, specular=0.8),
                4, size=16.0, location=(0.0, 2.0, 0.0))
    wall = add(bpy.ops.mesh.primitive_plane_add, "Wall",
               diffuse_material("WallMat", (0.70, 0.68, 0.62), checker=((0.25, 0.30, 0.45), 1.5)),
               5, size=16.0, location=(0.0, 6.0, 1.5), rotation=(math.pi / 2, 0.0, 0.0))
    wall.scale = (1.0, 3.0 / 16.0, 1.0)
    mirror = add(bpy.ops.mesh.primitive_plane_add, "Mirror",
                 principled_material("MirrorMat", (0.95, 0.95, 0.95), roughness=0.0, metallic=1.0),
                 6, size=3.0, location=(-3.4, 3.2, 1.3), rotation=(math.pi / 2, 0.0, math.radians(60)))
    red = add(bpy.ops.mesh.primitive_cube_add, "RedCube",
              diffuse_material("RedMat", (0.95, 0.10, 0.05)), 1, size=1.2, location=(-1.2, 3.0, 0.6),
              rotation=(0.0, 0.0, math.radians(25)))
    green = add(bpy.ops.mesh.primitive_uv_sphere_add, "GreenSphere",
                diffuse_material("GreenMat", (0.10, 0.90, 0.15)), 2, radius=0.6, segments=32, ring_count=16,
                location=(0.4, 2.2, 0.6))
    bpy.ops.object.shade_smooth()
    blue = add(bpy.ops.mesh.primitive_cylinder_add, "BlueCylinder",
               diffuse_material("BlueMat", (0.10, 0.25, 0.95)), 3, radius=0.45, depth=1.8, vertices=24,
               location=(2.2, 3.4, 0.9))
    gold = add(bpy.ops.mesh.primitive_uv_sphere_add, "GoldSphere",
               principled_material("GoldMat", (1.0, 0.75, 0.30), roughness=0.2, metallic=1.0),
               7, radius=0.5, segments=32, ring_count=16, location=(1.3, 1.0, 0.5))
    bpy.ops.object.shade_smooth()

    # The green sphere moves right; the camera slides right and pans a little.
    for f, loc in ((0, (-0.4, 2.2, 0.6)), (12, (1.6, 2.0, 0.6))):
        green.location = loc
        green.keyframe_insert("location", frame=f)
    set_linear(green)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 30.0
    cam_data.sensor_fit = "AUTO"
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.rotation_mode = "XYZ"
    for f, loc, rot_deg in ((0, (-1.0, -5.5, 2.2), (75.0, 0.0, -6.0)), (12, (0.6, -5.4, 2.2), (75.0, 0.0, 4.0))):
        cam.location = loc
        cam.rotation_euler = Euler([math.radians(a) for a in rot_deg], "XYZ")
        cam.keyframe_insert("location", frame=f)
        cam.keyframe_insert("rotation_euler", frame=f)
    set_linear(cam)

    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = 2.5
    sun_data.angle = math.radians(3.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = Euler((math.radians(45), math.radians(-15), math.radians(20)), "XYZ")
    scene.collection.objects.link(sun)
    area_data = bpy.data.lights.new("Area", type="AREA")
    area_data.energy = 250.0
    area_data.size = 2.0
    area = bpy.data.objects.new("Area", area_data)
    area.location = (2.0, -2.0, 4.5)
    area.rotation_euler = (Vector((0.0, 2.5, 0.5)) - area.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(area)
    return scene, cam, [floor, wall, mirror, red, green, blue, gold], ["GreenSphere"]


def configure_render(scene, output, filter_width, last_frame, light_passes=False, half=False):
    scene.render.resolution_x = WIDTH
    scene.render.resolution_y = HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = 1.0
    scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = False
    scene.cycles.seed = 0
    scene.view_layers[0].name = "ViewLayer"
    setup.configure(scene, output, light_passes=light_passes, half=half, samples=1, filter_width=filter_width,
                    frame_start=FRAME_START, frame_end=last_frame)


rowmajor = setup.rowmajor


def export_matrices(scene, cam, objects, output, moving=("Sphere",)):
    frames = {}
    export_frames = list(range(FRAME_START - 1, scene.frame_end + 2))
    for f in export_frames:
        scene.frame_set(f)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        frames[str(f)] = setup.camera_entry(scene, cam)
        frames[str(f)]["objects"] = {o.name: rowmajor(o.evaluated_get(depsgraph).matrix_world) for o in objects}
    scene.frame_set(FRAME_START)
    data = {
        "width": WIDTH,
        "height": HEIGHT,
        "frames": list(range(FRAME_START, scene.frame_end + 1)),
        "matrix_frames": export_frames,
        "files": ["frame_%04d.exr" % f for f in range(FRAME_START, scene.frame_end + 1)],
        "cameras": frames,
        "camera": {"lens_mm": cam.data.lens, "sensor_width_mm": cam.data.sensor_width,
                   "sensor_fit": cam.data.sensor_fit, "clip_start": cam.data.clip_start,
                   "clip_end": cam.data.clip_end},
        "pass_index": {o.name: o.pass_index for o in objects},
        "moving_objects": list(moving),
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
    text = setup.compact_json(data)
    with open(os.path.join(output, "cameras.json"), "w") as fh:
        fh.write(text + "\n")


def main():
    args = parse_args()
    global WIDTH, HEIGHT
    if args.size:
        WIDTH, HEIGHT = (int(v) for v in args.size.lower().split("x"))
    output = os.path.abspath(args.output)
    os.makedirs(output, exist_ok=True)
    clear_scene()
    if args.scene == "glossy":
        scene, cam, objects, moving = build_glossy_scene()
    else:
        (scene, cam, objects), moving = build_scene(), ["Sphere"]
    if args.save_blend:
        scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
        scene.render.resolution_percentage = 100
        scene.frame_start, scene.frame_end = FRAME_START, args.frames
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save_blend))
        return
    configure_render(scene, output, args.filter_width, args.frames, args.light_passes, args.half)
    export_matrices(scene, cam, objects, output, moving)
    bpy.ops.render.render(animation=True)
    if args.reference_samples > 0:
        # The reference: the same frames with many samples (animated seed, no denoising), as a
        # plain RGB EXR that `rtdenoise eval --reference` reads.
        setup.render_reference(scene, output, args.reference_samples, args.half)


if __name__ == "__main__":
    main()
