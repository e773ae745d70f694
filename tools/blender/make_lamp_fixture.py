"""A Cornell-like room lit by an emissive ceiling lamp, built as a Blender user would build it,
rendered with Cycles for the emitter-halo measurements of issue 12 (tests/fixtures/blender_lamp).

Run (Blender 3.4, Debian package `blender`):

    blender -b --factory-startup -P tools/blender/make_lamp_fixture.py -- \
        --output tests/fixtures/blender_lamp --reference-samples 2048

The scene, as a user models it in the UI: a room of planes (4 m wide, 4 m deep, 2.8 m high;
diffuse white, red and green walls), the lamp a mesh plane (Add > Mesh > Plane, 1 x 1 m)
with an Emission shader (strength 12), 2 mm below the ceiling with the plane's own normal (up:
Cycles mesh emitters are two-sided) and the default pass index 0 like every other object (so
the Object Index pass does not tell the lamp from the ceiling); a 0.7 m box on the floor that
slides 1.5 cm per frame; a still camera. Nothing else lights the room (black world).

The render set-up is tools/blender/rtdenoise_setup.py's (`configure` with `emission=True`: the
Emit and Environment passes, which rtdenoise reads as its emission buffer): 1 sample, animated
seed, half-float multilayer EXR, ZIP. The pixel filter is 0.01 px wide (`--filter-width`): the
1-sample frames are centre-sampled with any filter (nearly the same with Blender's default
1.5 px), but a many-sample reference is anti-aliased by it, and the lamp's anti-aliased edge
would count as every denoiser's error (tests/fixtures/blender_lamp/README.md). Writes
<output>/frame_NNNN.exr (96x54, frames 1-12 by default), cameras.json and, with
--reference-samples, reference/frame_NNNN.exr and render.json. `--no-emission` leaves the Emit
and Environment passes out (a user who did not enable them).
"""

import argparse
import math
import os
import sys

import bpy
from mathutils import Euler

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_fixture as mf  # noqa: E402  (materials, objects, scene clearing)
import rtdenoise_setup as setup  # noqa: E402

ROOM_W, ROOM_D, ROOM_H = 4.0, 4.0, 2.8
LAMP_SIZE, LAMP_GAP, LAMP_STRENGTH = 1.0, 0.002, 12.0


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_lamp_fixture.py")
    p.add_argument("--output", required=True)
    p.add_argument("--size", default="96x54", help="WxH (default 96x54)")
    p.add_argument("--frames", type=int, default=12, help="frames 1..N (default 12)")
    p.add_argument("--reference-samples", type=int, default=0)
    p.add_argument("--full-float", action="store_true", help="32-bit instead of half float")
    p.add_argument("--no-emission", action="store_true", help="leave the Emit and Environment passes out")
    p.add_argument("--filter-width", type=float, default=0.01,
                   help="Cycles' pixel filter width in px (default 0.01: the reference is the expectation of the "
                        "1-spp frames; Blender's default 1.5 anti-aliases the reference only)")
    p.add_argument("--camera-speed", type=float, default=0.0,
                   help="camera slide to the right, metres per frame (default 0: still)")
    return p.parse_args(argv)


def emission_material(name, strength):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (1.0, 0.95, 0.85, 1.0)
    em.inputs["Strength"].default_value = strength
    nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def plane(name, material, size, location, rotation=(0.0, 0.0, 0.0), scale=(1.0, 1.0, 1.0)):
    obj = mf.add(bpy.ops.mesh.primitive_plane_add, name, material, 0, size=size, location=location,
                 rotation=rotation)
    obj.scale = scale
    return obj


def build_scene(frames, camera_speed):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("World") if scene.world is None else scene.world
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes.get("Background").inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)

    white = mf.diffuse_material("White", (0.75, 0.75, 0.72))
    red = mf.diffuse_material("Red", (0.65, 0.08, 0.06))
    green = mf.diffuse_material("Green", (0.10, 0.55, 0.12))
    w, d, h = ROOM_W, ROOM_D, ROOM_H
    objects = [
        plane("Floor", white, 1.0, (0.0, d / 2, 0.0), scale=(w, d, 1.0)),
        # Ceiling and lamp face down (rotated 180 degrees about x) as a user flips the ceiling
        # plane; the lamp keeps the plane's default up-facing normal (two-sided emission).
        plane("Ceiling", white, 1.0, (0.0, d / 2, h), rotation=(math.pi, 0.0, 0.0), scale=(w, d, 1.0)),
        plane("Back", white, 1.0, (0.0, d, h / 2), rotation=(math.pi / 2, 0.0, 0.0), scale=(w, h, 1.0)),
        plane("Left", red, 1.0, (-w / 2, d / 2, h / 2), rotation=(0.0, math.pi / 2, 0.0), scale=(h, d, 1.0)),
        plane("Right", green, 1.0, (w / 2, d / 2, h / 2), rotation=(0.0, -math.pi / 2, 0.0), scale=(h, d, 1.0)),
        plane("Lamp", emission_material("Lamp", LAMP_STRENGTH), LAMP_SIZE, (0.0, d / 2, h - LAMP_GAP)),
    ]
    tall = mf.add(bpy.ops.mesh.primitive_cube_add, "TallBox", white, 0, size=1.0,
                  location=(0.8, 2.6, 0.7), rotation=(0.0, 0.0, math.radians(-20)))
    tall.scale = (0.7, 0.7, 1.4)
    cube = mf.add(bpy.ops.mesh.primitive_cube_add, "Cube", white, 0, size=0.7,
                  location=(-0.9, 1.6, 0.35), rotation=(0.0, 0.0, math.radians(25)))
    objects += [tall, cube]
    # The cube slides to the right, 1.5 cm per frame (linear).
    for f, x in ((0, -0.9), (frames + 1, -0.9 + 0.015 * (frames + 1))):
        cube.location.x = x
        cube.keyframe_insert("location", frame=f)
    mf.set_linear(cube)

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 20.0
    cam_data.sensor_fit = "AUTO"
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.rotation_mode = "XYZ"
    for f in (0, frames + 1):
        cam.location = (camera_speed * f, -2.0, 1.6)
        cam.rotation_euler = Euler((math.radians(90.0), 0.0, 0.0), "XYZ")
        cam.keyframe_insert("location", frame=f)
        cam.keyframe_insert("rotation_euler", frame=f)
    mf.set_linear(cam)
    return scene, cam, objects


def main():
    args = parse_args()
    width, height = (int(v) for v in args.size.lower().split("x"))
    output = os.path.abspath(args.output)
    os.makedirs(output, exist_ok=True)
    mf.clear_scene()
    scene, cam, objects = build_scene(args.frames, args.camera_speed)
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.cycles.seed = 0
    scene.view_layers[0].name = "ViewLayer"
    changes = setup.configure(scene, output, half=not args.full_float, samples=1, frame_start=1,
                              frame_end=args.frames, filter_width=args.filter_width, emission=not args.no_emission)
    print("make_lamp_fixture: %d setting(s) changed" % len(changes))
    setup.write_cameras(scene, cam, output)
    bpy.ops.render.render(animation=True)
    if args.reference_samples > 0:
        setup.render_reference(scene, output, args.reference_samples, not args.full_float)


if __name__ == "__main__":
    main()
