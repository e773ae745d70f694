#!/usr/bin/env python3
"""Check the conventions of the Blender fixture (python3 + numpy only).

    python3 tools/blender/check_fixture.py tests/fixtures/blender

Contains a minimal reader for single-part scanline OpenEXR files
(NONE / ZIPS / ZIP compression, HALF / FLOAT channels), which is all Blender's
OPEN_EXR_MULTILAYER output with codec ZIP or NONE needs.
"""

import json
import os
import struct
import sys
import zlib

import numpy as np

# ----------------------------------------------------------------- EXR reader


def _read_header(buf):
    if buf[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file")
    version = struct.unpack_from("<I", buf, 4)[0]
    if version & 0x1200:  # tiled (0x200) or multi-part (0x1000)
        raise ValueError("tiled / multi-part EXR not supported (flags 0x%x)" % version)
    pos = 8
    attrs = {}
    while buf[pos] != 0:
        end = buf.index(b"\0", pos)
        name = buf[pos:end].decode()
        pos = end + 1
        end = buf.index(b"\0", pos)
        typ = buf[pos:end].decode()
        pos = end + 1
        size = struct.unpack_from("<i", buf, pos)[0]
        pos += 4
        attrs[name] = (typ, buf[pos:pos + size])
        pos += size
    return attrs, pos + 1


def _chlist(raw):
    chans, pos = [], 0
    while raw[pos] != 0:
        end = raw.index(b"\0", pos)
        name = raw[pos:end].decode()
        ptype, _plin, xs, ys = struct.unpack_from("<iB3xii", raw, end + 1)
        if (xs, ys) != (1, 1):
            raise ValueError("subsampled channels not supported")
        chans.append((name, ptype))
        pos = end + 1 + 16
    return chans


def _unzip(data, expected):
    raw = np.frombuffer(zlib.decompress(data), dtype=np.uint8)
    if raw.size != expected:
        raise ValueError("bad ZIP block size")
    # undo the predictor, then de-interleave the two halves
    t = (np.cumsum(np.concatenate(([raw[0]], raw[1:].astype(np.int64) - 128))) & 0xFF).astype(np.uint8)
    half = (t.size + 1) // 2
    out = np.empty_like(t)
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return out.tobytes()


def read_exr(path):
    """Return ({channel name: float32 array [rows from top, x]}, header attrs)."""
    with open(path, "rb") as fh:
        buf = fh.read()
    attrs, pos = _read_header(buf)
    chans = _chlist(attrs["channels"][1])
    comp = attrs["compression"][1][0]
    lines_per_block = {0: 1, 2: 1, 3: 16}.get(comp)
    if lines_per_block is None:
        raise ValueError("compression %d not supported" % comp)
    xmin, ymin, xmax, ymax = struct.unpack("<iiii", attrs["dataWindow"][1])
    w, h = xmax - xmin + 1, ymax - ymin + 1
    nblocks = (h + lines_per_block - 1) // lines_per_block
    offsets = struct.unpack_from("<%dQ" % nblocks, buf, pos)
    bpp = {1: 2, 2: 4, 0: 4}
    dt = {1: "<f2", 2: "<f4", 0: "<u4"}
    out = {name: np.zeros((h, w), np.float32) for name, _ in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", buf, off)
        data = buf[off + 8: off + 8 + size]
        nl = min(lines_per_block, ymax + 1 - y)
        expected = nl * w * sum(bpp[t] for _, t in chans)
        if size < expected:
            data = _unzip(data, expected) if comp in (2, 3) else data
        p = 0
        for line in range(nl):
            row = y - ymin + line
            for name, t in chans:
                n = w * bpp[t]
                out[name][row] = np.frombuffer(data[p:p + n], dtype=dt[t]).astype(np.float32)
                p += n
    return out, attrs


# ------------------------------------------------------------------ helpers

VL = "ViewLayer."


def stack(ch, pass_name, comps):
    return np.stack([ch[VL + pass_name + "." + c] for c in comps], axis=-1)


def project(P, w2c, proj, W, H):
    """World points [...,3] -> (x, row-from-top) pixel coords, camera-space z."""
    Ph = np.concatenate([P, np.ones(P.shape[:-1] + (1,))], axis=-1)
    pc = Ph @ np.asarray(w2c).T
    clip = pc @ np.asarray(proj).T
    ndc = clip[..., :3] / clip[..., 3:4]
    x = (ndc[..., 0] + 1.0) * 0.5 * W
    row = (1.0 - ndc[..., 1]) * 0.5 * H
    return np.stack([x, row], axis=-1), pc[..., 2]


def stats(e):
    e = np.abs(np.asarray(e, dtype=np.float64))
    return "mean %.2e  max %.2e  (n=%d)" % (e.mean(), e.max(), e.size) if e.size else "n=0"


def main(folder):
    cams = json.load(open(os.path.join(folder, "cameras.json")))
    W, H = cams["width"], cams["height"]
    cam = {int(k): v for k, v in cams["cameras"].items()}
    pidx = cams["pass_index"]
    moving = {pidx[n] for n in cams["moving_objects"]}
    frames = {}
    for f, name in zip(cams["frames"], cams["files"]):
        frames[f], attrs = read_exr(os.path.join(folder, name))
    print("channels:", ", ".join(sorted(frames[cams["frames"][0]].keys())))
    print("filter: %s %.2f px" % (cams["render"]["filter_type"], cams["render"]["filter_width"]))

    jj, ii = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    centre = np.stack([ii + 0.5, jj + 0.5], axis=-1)

    agg = {k: [] for k in ("depth", "centre_dx", "centre_dy", "vec_exact", "vec_centre",
                            "vec_alt", "vecZW_exact", "mov_exact", "mov_centre",
                            "mov_static_guess", "n_floor", "n_wall", "dalb_diffcol",
                            "dnorm_norm", "dnorm_cam", "ddepth_depth", "ddepth_raylen",
                            "ddepth_near", "alpha", "vmag_static", "vmag_moving")}
    for f, ch in frames.items():
        P = stack(ch, "Position", "XYZ").astype(np.float64)
        N = stack(ch, "Normal", "XYZ").astype(np.float64)
        V = stack(ch, "Vector", "XYZW").astype(np.float64)
        depth = ch[VL + "Depth.Z"].astype(np.float64)
        idx = ch[VL + "IndexOB.X"]
        hit = depth < 1e9
        c = cam[f]
        xy, zc = project(P, c["world_to_camera"], c["projection"], W, H)

        print("frame %d: IndexOB values %s, background pixels %d, background Depth %s, "
              "background Position %s, Vector %s" % (
                  f, sorted(set(np.unique(idx).tolist())), int((~hit).sum()),
                  np.unique(depth[~hit])[:3], np.unique(P[~hit].reshape(-1))[:3],
                  np.unique(V[~hit].reshape(-1))[:3]))

        agg["depth"].append((depth + zc)[hit])
        d = xy - centre
        agg["centre_dx"].append(d[..., 0][hit])
        agg["centre_dy"].append(d[..., 1][hit])
        agg["alpha"].append(ch[VL + "Combined.A"] - 1.0)

        floor, wall = (idx == pidx["Floor"]) & hit, (idx == pidx["Wall"]) & hit
        agg["n_floor"].append((N[floor] - [0, 0, 1]).ravel())
        agg["n_wall"].append((N[wall] - [0, -1, 0]).ravel())
        agg["dalb_diffcol"].append((stack(ch, "Denoising Albedo", "RGB")
                                    - stack(ch, "DiffCol", "RGB"))[hit].ravel())
        DN = stack(ch, "Denoising Normal", "XYZ")
        agg["dnorm_norm"].append((DN - N)[hit].ravel())
        # camera space with z pointing away from the camera (Cycles' camera space)
        R = np.diag([1.0, 1.0, -1.0]) @ np.asarray(c["world_to_camera"])[:3, :3]
        agg["dnorm_cam"].append((DN - N @ R.T)[hit].ravel())
        dd = ch[VL + "Denoising Depth.Z"].astype(np.float64)
        cpos = np.asarray(c["camera_to_world"])[:3, 3]
        agg["ddepth_depth"].append((dd - depth)[hit])
        raylen = np.linalg.norm(P - cpos, axis=-1)
        agg["ddepth_raylen"].append((dd - raylen)[hit])
        # ray length measured from where the ray leaves the near clip plane
        near = cams["camera"]["clip_start"]
        agg["ddepth_near"].append((dd - raylen * (1.0 - near / np.where(hit, depth, 1.0)))[hit])

        static = hit & ~np.isin(idx, list(moving))
        mov = hit & np.isin(idx, list(moving))
        agg["vmag_static"].append(np.linalg.norm(V[..., :2], axis=-1)[static])
        agg["vmag_moving"].append(np.linalg.norm(V[..., :2], axis=-1)[mov])
        # Vector.XY: previous frame
        if f - 1 in cam:
            p = cam[f - 1]
            xy_prev, _ = project(P, p["world_to_camera"], p["projection"], W, H)
            vec_img = np.stack([V[..., 0], -V[..., 1]], axis=-1)  # y up -> rows down
            agg["vec_exact"].append(((xy_prev - xy) - vec_img)[static].ravel())
            agg["vec_centre"].append(((centre + vec_img) - xy_prev)[static].ravel())
            agg["vec_alt"].append(((xy_prev - xy) - V[..., :2])[static].ravel())  # no y flip
            # moving object: bring P back with the object's previous transform
            for name in cams["moving_objects"]:
                m = mov & (idx == pidx[name])
                Mc = np.asarray(c["objects"][name])
                Mp = np.asarray(p["objects"][name])
                Ph = np.concatenate([P, np.ones(P.shape[:-1] + (1,))], -1)
                Pprev = (Ph @ (Mp @ np.linalg.inv(Mc)).T)[..., :3]
                xy_mp, _ = project(Pprev, p["world_to_camera"], p["projection"], W, H)
                agg["mov_exact"].append(((xy_mp - xy) - vec_img)[m].ravel())
                agg["mov_centre"].append(((centre + vec_img) - xy_mp)[m].ravel())
                agg["mov_static_guess"].append(((xy_prev - xy) - vec_img)[m].ravel())
        # Vector.ZW: next frame
        if f + 1 in cam:
            n = cam[f + 1]
            xy_next, _ = project(P, n["world_to_camera"], n["projection"], W, H)
            vzw = np.stack([V[..., 2], -V[..., 3]], axis=-1)
            agg["vecZW_exact"].append(((xy - xy_next) - vzw)[static].ravel())

    cat = {k: np.concatenate(v).ravel() if v else np.zeros(0) for k, v in agg.items()}
    print()
    print("Depth + z_cam(Position)             :", stats(cat["depth"]))
    print("proj(Position) - pixel centre, x    : mean %+.3f  min %+.3f  max %+.3f" % (
        cat["centre_dx"].mean(), cat["centre_dx"].min(), cat["centre_dx"].max()))
    print("proj(Position) - pixel centre, row  : mean %+.3f  min %+.3f  max %+.3f" % (
        cat["centre_dy"].mean(), cat["centre_dy"].min(), cat["centre_dy"].max()))
    print("static: (proj_prev(P)-proj(P)) - (Vx,-Vy)        :", stats(cat["vec_exact"]))
    print("static: centre + (Vx,-Vy) - proj_prev(P)         :", stats(cat["vec_centre"]))
    print("static: (proj_prev(P)-proj(P)) - (Vx,+Vy) [wrong]:", stats(cat["vec_alt"]))
    print("static: (proj(P)-proj_next(P)) - (Vz,-Vw)        :", stats(cat["vecZW_exact"]))
    print("moving: (proj_prev(M_prev M^-1 P)-proj(P)) - (Vx,-Vy):", stats(cat["mov_exact"]))
    print("moving: centre + (Vx,-Vy) - proj_prev(M_prev M^-1 P) :", stats(cat["mov_centre"]))
    print("moving: same but ignoring object motion [wrong]      :", stats(cat["mov_static_guess"]))
    print("Normal - (0,0,1) on floor           :", stats(cat["n_floor"]))
    print("Normal - (0,-1,0) on wall           :", stats(cat["n_wall"]))
    print("Denoising Albedo - DiffCol          :", stats(cat["dalb_diffcol"]))
    print("Denoising Normal - Normal           :", stats(cat["dnorm_norm"]))
    print("Denoising Normal - diag(1,1,-1) R_w2c Normal:", stats(cat["dnorm_cam"]))
    print("Denoising Depth - Depth             :", stats(cat["ddepth_depth"]))
    print("Denoising Depth - ray length        :", stats(cat["ddepth_raylen"]))
    print("Denoising Depth - ray length*(1-clip_start/Depth):", stats(cat["ddepth_near"]))
    print("Combined.A - 1                      :", stats(cat["alpha"]))
    print("|Vector.XY| static pixels           : mean %.2f max %.2f px" % (
        cat["vmag_static"].mean(), cat["vmag_static"].max()))
    print("|Vector.XY| moving-object pixels    : mean %.2f max %.2f px" % (
        cat["vmag_moving"].mean(), cat["vmag_moving"].max()))

    # The conventions the fixture is meant to pin down; fail loudly if they change.
    tol = {"depth": 1e-4, "vec_exact": 1e-3, "vecZW_exact": 1e-3, "mov_exact": 1e-3,
           "n_floor": 1e-5, "n_wall": 1e-5, "dnorm_cam": 1e-4, "ddepth_near": 1e-4,
           "dalb_diffcol": 1e-6, "centre_dx": 0.01, "centre_dy": 0.01}
    bad = [k for k, t in tol.items() if cat[k].size == 0 or np.abs(cat[k]).max() > t]
    print("\nRESULT:", "OK" if not bad else "FAILED " + ", ".join(bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "tests/fixtures/blender"))
