"""Build 480x270 training/eval caches (one .npz per video) from generated PNG videos or the real mp4.

  python prep_data.py generated DATA_ROOT OUT_DIR [--every 3] [--zoom]
  python prep_data.py real SAMPLE_VIDEO_DIR OUT_FILE
  python prep_data.py generated DATA_ROOT OUT_DIR --scenario fluid --every 5 [--rgb png|mp4|alternate]
  python prep_data.py generated DATA_ROOT OUT_DIR --scenario ball --every 5 [--rgb png|mp4|alternate]
  python prep_data.py generated DATA_ROOT OUT_DIR --scenario cloth --every 5 [--rgb png|mp4|alternate]

Cache: imgs [F,270,480,3] uint8, inst [F,270,480] uint8 (instance ids), keys [F] (annotation keys),
classes [256] int64 (instance id -> class id, 0 = ignore).
Frame file frame_NNNNN.png (and mp4 frame i, 0-based) is annotation key i+1; checked on every video.

Fluid (--scenario fluid): the ids of `inst` are target instances, not the generator's: the five
parts of a container are one container, each stick and emitter is its own, and the fluids of one
colour ("<C> Fluid", "Later Emitted <C> Fluid") are united and split per frame into connected
components (8-connectivity after a 3x3 dilation; components under 6 pixels are background), all
of class fluid. --rgb mp4 takes the RGB from output_Full.mp4 (decoded by ffmpeg as the Rust side
does), --rgb alternate takes it from the PNG and the mp4 on alternate cached frames (`mp4` [F] bool
in the cache); masks always come from the exact PNG segmentation.

Ball (--scenario ball): the fluid path without groups or components: every ball, floating wall,
ramp and floor piece is its own instance (its generator id kept; common.ball_groups); the
stadium behind them is not segmented (background). --rgb as for fluid.

Cloth (--scenario cloth): as ball: every cloth, pillar and plate is its own instance (its
generator id kept; common.cloth_groups); the table (and a cube, which the generator practically
never writes) is background, the room behind is not segmented. --rgb as for fluid.
"""
import argparse
import glob
import os

import numpy as np
from PIL import Image

from common import (IN_H, IN_W, ball_groups, box_average, class_of_name, cloth_groups, decode_video,
                    downscale_instance_map, fluid_groups, frame_record, load_annotations, scenario, seg_to_instances,
                    split_components)


def check_boxes(inst, boxes, key, what):
    """Every annotated box must equal the box of its instance's pixels (exact for generated)."""
    bad = 0
    for iid, (x0, y0, w, h) in boxes.items():
        ys, xs = np.nonzero(inst == iid)
        if len(xs) == 0:
            bad += 1
            continue
        if (xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1) != (x0, y0, w, h):
            bad += 1
    return bad


def class_table(names):
    t = np.zeros(256, np.int64)
    for iid, n in names.items():
        t[iid] = class_of_name(n)
    return t


def zoom_window(full, key, vid):
    """A 480x270 window of the 960x540 frame at its own resolution (objects twice as large as in
    the box-averaged frame), centred near the objects' pixels with a jitter drawn from the video
    id and the annotation key (deterministic)."""
    h, w = full.shape
    rng = np.random.default_rng(vid * 100003 + key)
    ys, xs = np.nonzero(full)
    cy, cx = (ys.mean(), xs.mean()) if len(xs) else (h / 2, w / 2)
    cy += rng.uniform(-0.25, 0.25) * IN_H
    cx += rng.uniform(-0.35, 0.35) * IN_W
    y0 = int(np.clip(round(cy - IN_H / 2), 0, h - IN_H))
    x0 = int(np.clip(round(cx - IN_W / 2), 0, w - IN_W))
    return y0, x0


def prep_generated(root, out, every, zoom=False):
    os.makedirs(out, exist_ok=True)
    vids = sorted((p for p in glob.glob(os.path.join(root, "pulley_group", "*")) if os.path.basename(p).isdigit()), key=lambda p: int(os.path.basename(p)))
    for vn, vd in enumerate(vids):
        vid = int(os.path.basename(vd))
        dst = os.path.join(out, f"{vid}.npz")
        if os.path.exists(dst):
            continue
        try:
            names, per_frame = load_annotations(os.path.join(vd, "outputs.json"))
        except (OSError, ValueError):
            continue  # still being generated
        files = sorted(glob.glob(os.path.join(vd, "frames", "output_Full_ori", "frame_*.png")))
        segs = glob.glob(os.path.join(vd, "frames", "output_Full_seg", "frame_*.png"))
        if not files or len(files) != len(per_frame) or len(segs) != len(files):
            continue  # incomplete
        cls = class_table(names)
        imgs, insts, keys = [], [], []
        for i in range(vid % every, len(files), every):
            key = i + 1
            boxes, colours = frame_record(per_frame, key)
            rgb = np.asarray(Image.open(files[i]).convert("RGB"))
            seg = np.asarray(Image.open(files[i].replace("output_Full_ori", "output_Full_seg")).convert("RGB"))
            full = seg_to_instances(seg, colours)
            if i == vid % every or i == len(files) // 2:
                assert check_boxes(full, boxes, key, vd) == 0, f"frame {i} != key {key} in {vd}"
            f = rgb.shape[0] // IN_H
            if zoom and f != 2:
                raise SystemExit(f"{vd}: --zoom needs 960x540 frames (2x the cache size), got {rgb.shape[1]}x{rgb.shape[0]}")
            if zoom:
                y0, x0 = zoom_window(full, key, vid)
                imgs.append(np.ascontiguousarray(rgb[y0:y0 + IN_H, x0:x0 + IN_W]))
                insts.append(np.ascontiguousarray(full[y0:y0 + IN_H, x0:x0 + IN_W]).astype(np.uint8))
            else:
                imgs.append(box_average(rgb, f))
                insts.append(downscale_instance_map(full, f, list(colours)))
            keys.append(key)
        np.savez_compressed(dst, imgs=np.stack(imgs), inst=np.stack(insts), keys=np.array(keys), classes=cls)
        print(f"{vd}: {len(keys)} frames", flush=True)


def mp4_rgb(vd, shape, n, pngs):
    """All frames of the video's output_Full.mp4 ([n,H,W,3]), checked against the PNG frames:
    summed over 10 frames spread over the video, mp4 frame i must be closer to PNG frame i than to
    PNG frame i-1 or i+1 (mean |difference| after a 5x5 box average: single frames are not enough,
    as on still frames the encoder's copied blocks and the per-frame sensor noise of randomised
    videos make the neighbours as close)."""
    rgb = decode_video(os.path.join(vd, "output_Full.mp4"), shape[1], shape[0], passthrough=True)
    if len(rgb) != n:
        raise SystemExit(f"{vd}: output_Full.mp4 has {len(rgb)} frames, {n} PNG frames")
    png = {}
    total = {-1: 0.0, 0: 0.0, 1: 0.0}
    for i in np.linspace(n // 10, n - 2, 10).round().astype(int):
        a = box_average(rgb[i], 5).astype(np.int16)
        for off in total:
            j = int(i) + off
            if j not in png:
                png[j] = box_average(np.asarray(Image.open(pngs[j]).convert("RGB")), 5).astype(np.int16)
            total[off] += float(np.abs(a - png[j]).mean())
    if total[0] >= min(total[-1], total[1]):
        raise SystemExit(f"{vd}: the mp4 frames are not closest to the PNG frames of the same index: {total}")
    return rgb


def prep_fluid(root, out, every, rgb_from="png", folder="fluid_slides", join=1, groups=fluid_groups):
    """Caches of generated fluid videos (see the module doc); no real-video part. With
    groups=ball_groups and folder soft_body, of ball videos, with groups=cloth_groups and folder
    cloth_collision, of cloth videos (no fluid, so nothing is split)."""
    os.makedirs(out, exist_ok=True)
    vids = sorted((p for p in glob.glob(os.path.join(root, folder, "*")) if os.path.basename(p).isdigit()),
                  key=lambda p: int(os.path.basename(p)))
    for vd in vids:
        vid = int(os.path.basename(vd))
        dst = os.path.join(out, f"{vid}.npz")
        if os.path.exists(dst):
            continue
        try:
            names, per_frame = load_annotations(os.path.join(vd, "outputs.json"))
        except (OSError, ValueError):
            continue  # still being generated
        files = sorted(glob.glob(os.path.join(vd, "frames", "output_Full_ori", "frame_*.png")))
        segs = glob.glob(os.path.join(vd, "frames", "output_Full_seg", "frame_*.png"))
        if not files or len(files) != len(per_frame) or len(segs) != len(files):
            continue  # incomplete
        lut, cls, fluid_ids, first_free, unknown = groups(names)
        if unknown:
            print(f"{vd}: names taken as background: {unknown}", flush=True)
        frames = list(range(vid % every, len(files), every))
        shape = np.asarray(Image.open(files[0])).shape
        mp4 = [rgb_from == "mp4" or (rgb_from == "alternate" and k % 2 == 1) for k in range(len(frames))]
        video = mp4_rgb(vd, shape, len(files), files) if any(mp4) else None
        imgs, insts, keys, most = [], [], [], 0
        for k, i in enumerate(frames):
            key = i + 1
            boxes, colours = frame_record(per_frame, key)
            rgb = video[i] if mp4[k] else np.asarray(Image.open(files[i]).convert("RGB"))
            seg = np.asarray(Image.open(files[i].replace("output_Full_ori", "output_Full_seg")).convert("RGB"))
            full = seg_to_instances(seg, colours)
            if k == 0 or k == len(frames) // 2:
                assert check_boxes(full, boxes, key, vd) == 0, f"frame {i} != key {key} in {vd}"
            f = rgb.shape[0] // IN_H
            g = lut[full]  # generator ids -> objects (containers united, fluids united per colour)
            if f != 1:
                g = downscale_instance_map(g, f, [int(x) for x in np.unique(g) if x])
                rgb = box_average(rgb, f)
            regions = fluid_ids
            if join > 1 and len(fluid_ids) > 1:
                # Regions: the fluids of every colour together (drops of two fluids interleave in
                # a spray or a cup); the colour of each pixel names its fluid at answer time.
                g = np.where(np.isin(g, fluid_ids), fluid_ids[0], g).astype(g.dtype)
                regions = fluid_ids[:1]
            g, n = split_components(g, regions, first_free, join=join)
            most = max(most, int(len(np.unique(g))) - 1)
            imgs.append(rgb)
            insts.append(g)
            keys.append(key)
        extra = {"mp4": np.array(mp4)} if rgb_from != "png" else {}
        np.savez_compressed(dst, imgs=np.stack(imgs), inst=np.stack(insts), keys=np.array(keys), classes=cls, **extra)
        print(f"{vd}: {len(keys)} frames ({sum(mp4)} RGB from the mp4), at most {most} instances in a frame",
              flush=True)


def prep_real(vd, out, threshold=80.0):
    names, per_frame = load_annotations(os.path.join(vd, "outputs.json"))
    rgb = decode_video(os.path.join(vd, "output_Full.mp4"), 1920, 1080)
    seg = decode_video(os.path.join(vd, "output_Full_seg.mp4"), 1920, 1080)
    n = len(rgb)
    # Mapping check: mean IoU of annotated boxes with mask boxes for offsets 0, 1, 2 on a few frames.
    def mean_iou(i, key):
        boxes, colours = frame_record(per_frame, key)
        inst = seg_to_instances(seg[i], colours, threshold)
        ious = []
        for iid, (x0, y0, w, h) in boxes.items():
            ys, xs = np.nonzero(inst == iid)
            if len(xs) < 20:
                continue
            a = (x0, y0, x0 + w, y0 + h)
            b = (xs.min(), ys.min(), xs.max() + 1, ys.max() + 1)
            iw = max(0, min(a[2], b[2]) - max(a[0], b[0]))
            ih = max(0, min(a[3], b[3]) - max(a[1], b[1]))
            inter = iw * ih
            ious.append(inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter))
        return float(np.mean(ious)) if ious else 0.0
    for i in (10, 60, 120):
        print("mp4 frame", i, {off: round(mean_iou(i, i + off), 4) for off in (0, 1, 2) if 1 <= i + off <= n})
    cls = class_table(names)
    imgs, insts, keys = [], [], []
    for i in range(n):
        key = i + 1
        _, colours = frame_record(per_frame, key)
        full = seg_to_instances(seg[i], colours, threshold)
        imgs.append(box_average(rgb[i], 5))
        insts.append(downscale_instance_map(full, 4, list(colours)))
        keys.append(key)
    np.savez_compressed(out, imgs=np.stack(imgs), inst=np.stack(insts), keys=np.array(keys), classes=cls)
    print(out, n, "frames; names", names)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["generated", "real"])
    ap.add_argument("src")
    ap.add_argument("out")
    ap.add_argument("--scenario", default="rope", choices=["rope", "fluid", "ball", "cloth"])
    ap.add_argument("--rgb", default="png", choices=["png", "mp4", "alternate"],
                    help="fluid, ball, cloth: where the RGB comes from (the masks always come from the PNG segmentation)")
    ap.add_argument("--every", type=int, default=3)
    ap.add_argument("--fluid-join", type=int, default=1,
                    help="fluid: drops within 2*J pixels are one instance; J > 1 also fills the gaps between "
                         "them (a closing by the (2J+1)-square) and unites the fluids of all colours (fluid regions)")
    ap.add_argument("--zoom", action="store_true",
                    help="480x270 windows of the 960x540 frames at full resolution (a 2x camera zoom "
                         "with real detail) instead of the box-averaged whole frame")
    a = ap.parse_args()
    if a.scenario == "fluid":
        if a.mode != "generated" or a.zoom:
            raise SystemExit("fluid: generated videos only, without --zoom")
        prep_fluid(a.src, a.out, a.every, a.rgb, scenario("fluid")["folder"], a.fluid_join)
    elif a.scenario == "ball":
        if a.mode != "generated" or a.zoom or a.fluid_join != 1:
            raise SystemExit("ball: generated videos only, without --zoom or --fluid-join")
        prep_fluid(a.src, a.out, a.every, a.rgb, scenario("ball")["folder"], groups=ball_groups)
    elif a.scenario == "cloth":
        if a.mode != "generated" or a.zoom or a.fluid_join != 1:
            raise SystemExit("cloth: generated videos only, without --zoom or --fluid-join")
        prep_fluid(a.src, a.out, a.every, a.rgb, scenario("cloth")["folder"], groups=cloth_groups)
    elif a.rgb != "png":
        raise SystemExit("--rgb: fluid, ball and cloth only")
    elif a.mode == "generated":
        prep_generated(a.src, a.out, a.every, a.zoom)
    else:
        prep_real(a.src, a.out)
