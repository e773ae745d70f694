"""Set up any .blend for rtdenoise and render it: the passes rtdenoise reads, 1 sample, and
cameras.json with the camera of every frame.

Run (Blender 3.4, Debian package `blender`) on your own scene:

    blender -b my_scene.blend -P tools/blender/rtdenoise_setup.py -- --output renders/my_scene

which sets the scene up (below), writes renders/my_scene/cameras.json and renders
renders/my_scene/frame_NNNN.exr (multilayer EXR), which `rtdenoise denoise`, `compare` and
`pack` read as they are. Options:

  --frames A-B            frame range (default: the scene's)
  --light-passes          also Cycles' light passes (diffuse / glossy / transmission direct,
                          indirect, colour; emission; environment): SVGF's lobes
  --emission              also Cycles' Emission and Environment passes (included in
                          --light-passes): visible lamps and the sky, which rtdenoise
                          separates and keeps out of the filters (docs/blender.md)
  --half                  16-bit half float EXR instead of 32-bit
  --samples N             samples per pixel of the noisy frames (default 1)
  --reference-samples N   also render <output>/reference/frame_NNNN.exr with N samples (RGB EXR,
                          what `rtdenoise compare --reference` reads) and <output>/render.json
                          with that sample count (shown in the report)
  --filter-width W        Cycles' pixel filter width in pixels (default: the scene's)
  --camera NAME           camera object (default: the scene's camera)
  --view-layer NAME       view layer to render (default: the first); the others are disabled
  --no-render             set up and write cameras.json only
  --save FILE.blend       save the set-up scene

What it changes, and why (docs/blender.md): engine Cycles on the CPU; samples 1 without
adaptive sampling, denoising or motion blur (the Vector pass needs motion blur off); an
animated seed (a different noise pattern per frame, as a real-time renderer has); the passes
Combined, Normal, Z, Vector, Position, Object Index, Diffuse Color and Denoising Data (albedo);
output OPEN_EXR_MULTILAYER, ZIP. It prints each setting it changed.

make_fixture.py builds the committed fixtures with the same functions (configure, camera_entry).
"""

import argparse
import json
import os
import re
import sys

import bpy


def _set(obj, attr, value, changes, label):
    """Sets obj.attr = value, recording the change if it differs."""
    old = getattr(obj, attr)
    if old != value:
        setattr(obj, attr, value)
        changes.append("%s: %r -> %r" % (label, old, value))


def configure(scene, output, light_passes=False, half=False, samples=1, filter_width=None,
              view_layer=None, frame_start=None, frame_end=None, emission=False):
    """Sets `scene` up for rtdenoise (module docstring); returns the changes made, as text.
    `emission` enables only the Emit and Environment passes (which `light_passes` includes):
    rtdenoise's emission buffer, which keeps visible lamps and the sky out of the filters."""
    changes = []
    _set(scene.render, "engine", "CYCLES", changes, "render engine")
    _set(scene.cycles, "device", "CPU", changes, "Cycles device")
    _set(scene.render, "use_motion_blur", False, changes, "motion blur (the Vector pass needs it off)")
    _set(scene.render, "use_border", False, changes, "render border")
    if frame_start is not None:
        _set(scene, "frame_start", frame_start, changes, "first frame")
    if frame_end is not None:
        _set(scene, "frame_end", frame_end, changes, "last frame")
    cy = scene.cycles
    _set(cy, "samples", samples, changes, "samples")
    _set(cy, "use_adaptive_sampling", False, changes, "adaptive sampling")
    _set(cy, "use_denoising", False, changes, "denoising")
    _set(cy, "use_preview_denoising", False, changes, "viewport denoising")
    _set(cy, "use_animated_seed", True, changes, "animated seed")
    if filter_width is not None:
        _set(cy, "filter_width", filter_width, changes, "pixel filter width")

    layers = list(scene.view_layers)
    vl = next((l for l in layers if l.name == view_layer), None) if view_layer else layers[0]
    if vl is None:
        raise SystemExit("rtdenoise_setup: no view layer '%s' (there are: %s)"
                         % (view_layer, ", ".join(l.name for l in layers)))
    for other in layers:
        _set(other, "use", other == vl, changes, "view layer '%s' rendered" % other.name)
    passes = ["combined", "normal", "vector", "z", "position", "object_index", "diffuse_color"]
    if light_passes:
        passes += ["%s_%s" % (lobe, part) for lobe in ("diffuse", "glossy", "transmission")
                   for part in ("direct", "indirect", "color")]
    if light_passes or emission:
        passes += ["emit", "environment"]
    for p in passes:
        _set(vl, "use_pass_" + p, True, changes, "pass " + p)
    _set(vl.cycles, "denoising_store_passes", True, changes, "pass Denoising Data (albedo)")

    img = scene.render.image_settings
    _set(img, "file_format", "OPEN_EXR_MULTILAYER", changes, "file format")
    _set(img, "color_depth", "16" if half else "32", changes, "EXR depth")
    _set(img, "exr_codec", "ZIP", changes, "EXR codec")
    scene.render.use_file_extension = True
    scene.render.filepath = os.path.join(output, "frame_####")
    return changes


def resolution(scene):
    r = scene.render
    return (r.resolution_x * r.resolution_percentage // 100, r.resolution_y * r.resolution_percentage // 100)


def rowmajor(m):
    return [[float(m[r][c]) for c in range(4)] for r in range(4)]


def camera_entry(scene, cam):
    """The camera of the current frame as cameras.json holds it: world_to_camera (and its
    inverse) and the OpenGL-style projection for the render resolution, row-major."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    cam_eval = cam.evaluated_get(depsgraph)
    w, h = resolution(scene)
    return {
        "world_to_camera": rowmajor(cam_eval.matrix_world.inverted()),
        "camera_to_world": rowmajor(cam_eval.matrix_world),
        "projection": rowmajor(cam_eval.calc_matrix_camera(depsgraph, x=w, y=h)),
    }


def compact_json(data):
    """JSON with each list of numbers (a matrix row, a frame list) on one line."""
    text = json.dumps(data, indent=1)
    return re.sub(r"\[\s*(-?[0-9][^\[\]{}\"]*?)\s*\]",
                  lambda m: "[" + ", ".join(v.strip() for v in m.group(1).split(",")) + "]", text)


def write_cameras(scene, cam, output):
    """cameras.json for the scene's frames (the format rtdenoise reads: docs/sequence-format.md)."""
    frames = {}
    for f in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(f)
        frames[str(f)] = camera_entry(scene, cam)
    scene.frame_set(scene.frame_start)
    w, h = resolution(scene)
    data = {"generator": "tools/blender/rtdenoise_setup.py", "blender": bpy.app.version_string,
            "width": w, "height": h, "camera_object": cam.name, "cameras": frames,
            "conventions": "row-major 4x4, Blender world space, column vectors; the camera looks "
                           "down -Z; projection = calc_matrix_camera(x=width, y=height)"}
    path = os.path.join(output, "cameras.json")
    with open(path, "w") as fh:
        fh.write(compact_json(data) + "\n")
    return path


def render_reference(scene, output, samples, half):
    """<output>/reference/frame_NNNN.exr: the same frames with `samples` samples, RGB EXR."""
    scene.cycles.samples = samples
    img = scene.render.image_settings
    img.file_format = "OPEN_EXR"
    img.color_mode = "RGB"
    img.color_depth = "16" if half else "32"
    os.makedirs(os.path.join(output, "reference"), exist_ok=True)
    scene.render.filepath = os.path.join(output, "reference", "frame_####")
    bpy.ops.render.render(animation=True)
    # The sample count where `rtdenoise compare` looks for it (as `rtdenoise render` writes it).
    with open(os.path.join(output, "render.json"), "w") as fh:
        json.dump({"generator": "tools/blender/rtdenoise_setup.py", "blender": bpy.app.version_string,
                   "reference": {"dir": "reference", "spp": samples}}, fh, indent=1)
        fh.write("\n")


def parse_args(argv):
    p = argparse.ArgumentParser(prog="rtdenoise_setup.py", description=__doc__.split("\n")[0])
    p.add_argument("--output", required=True)
    p.add_argument("--frames", default=None, help="A-B")
    p.add_argument("--light-passes", action="store_true")
    p.add_argument("--emission", action="store_true")
    p.add_argument("--half", action="store_true")
    p.add_argument("--samples", type=int, default=1)
    p.add_argument("--reference-samples", type=int, default=0)
    p.add_argument("--filter-width", type=float, default=None)
    p.add_argument("--camera", default=None)
    p.add_argument("--view-layer", default=None)
    p.add_argument("--no-render", action="store_true")
    p.add_argument("--save", default=None)
    a = p.parse_args(argv)
    if a.frames is not None and not re.fullmatch(r"\d+-\d+", a.frames):
        p.error("--frames: expected A-B, e.g. 1-24")
    if a.samples < 1 or a.reference_samples < 0:
        p.error("--samples must be >= 1 and --reference-samples >= 0")
    return a


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    a = parse_args(argv)
    scene = bpy.context.scene
    cam = bpy.data.objects.get(a.camera) if a.camera else scene.camera
    if cam is None or cam.type != "CAMERA":
        raise SystemExit("rtdenoise_setup: no camera%s (give --camera NAME)" % (" '%s'" % a.camera if a.camera else ""))
    scene.camera = cam
    output = os.path.abspath(a.output)
    os.makedirs(output, exist_ok=True)
    start, end = (int(v) for v in a.frames.split("-")) if a.frames else (None, None)
    changes = configure(scene, output, a.light_passes, a.half, a.samples, a.filter_width, a.view_layer, start, end,
                        emission=a.emission)
    print("rtdenoise_setup: %d setting(s) changed%s" % (len(changes), "".join("\n  " + c for c in changes)))
    print("rtdenoise_setup: wrote", write_cameras(scene, cam, output))
    if a.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(a.save), copy=True)
        print("rtdenoise_setup: saved", a.save)
    if a.no_render:
        return
    bpy.ops.render.render(animation=True)
    if a.reference_samples > 0:
        render_reference(scene, output, a.reference_samples, a.half)
    print("rtdenoise_setup: rendered frames %d-%d into %s" % (scene.frame_start, scene.frame_end, output))


if __name__ == "__main__":
    main()
