"""Shared helpers: class contract, downscaling, annotation reading (numpy + PIL only)."""
import json
import os

import numpy as np

# FIXED contract with the Rust side: labels are 1-based, 0 is background.
CLASSES = {
    1: "cube",
    2: "sphere",
    3: "rope",
    4: "fixed point",
    5: "solid static pulley",
    6: "hollow static pulley",
    7: "solid dynamic pulley",
    8: "hollow dynamic pulley",
}
NUM_CLASSES = 9  # including background
IN_W, IN_H = 480, 270
MIN_PIXELS = 6


def class_of_name(name):
    """Class id from an Id2ObjectNameDict name ("Pink Hollow Static Pulley (0 5)"); 0 = ignore."""
    w = name.lower()
    if "pulley" in w:
        hollow = "hollow" in w
        dynamic = "dynamic" in w
        return {(False, False): 5, (True, False): 6, (False, True): 7, (True, True): 8}[(hollow, dynamic)]
    if "rope" in w:
        return 3
    if "fixed point" in w:
        return 4
    if "sphere" in w:
        return 2
    if "cube" in w:
        return 1
    return 0  # "Solver" and anything unknown


def box_average(img, f):
    """uint8 HxWxC -> (H/f)x(W/f)xC by exact fxf box average, rounded half up."""
    s = np.zeros((img.shape[0] // f, img.shape[1] // f, img.shape[2]), np.uint32)
    for dy in range(f):
        for dx in range(f):
            s += img[dy::f, dx::f]
    n = f * f
    return ((s * 2 + n) // (2 * n)).astype(np.uint8)


def downscale_instance_map(inst, f, ids):
    """Instance-id map HxW (uint8) -> (H/f)x(W/f): each output pixel gets the instance with the
    largest coverage of its fxf block if that coverage is >= 50%, else 0 (background)."""
    if f == 2:  # fast path: a non-zero id covering >= 2 of the 4 pixels (the majority one, else the first)
        p = [inst[0::2, 0::2], inst[0::2, 1::2], inst[1::2, 0::2], inst[1::2, 1::2]]
        out = np.zeros(p[0].shape, np.uint8)
        best = np.zeros(p[0].shape, np.int32)
        for x in p:
            cnt = sum((q == x).astype(np.int32) for q in p)
            take = (x != 0) & (cnt >= 2) & (cnt > best)
            out[take] = x[take]
            best[take] = cnt[take]
        return out
    h, w = inst.shape
    blocks = inst.reshape(h // f, f, w // f, f)
    out = np.zeros((h // f, w // f), np.uint8)
    best = np.zeros((h // f, w // f), np.int32)
    need = (f * f + 1) // 2
    for i in ids:
        cnt = (blocks == i).sum(axis=(1, 3))
        take = (cnt >= need) & (cnt > best)
        out[take] = i
        best = np.maximum(best, np.where(cnt >= need, cnt, 0))
    return out


def load_annotations(path):
    d = json.load(open(path))
    ia = d["imgAnnotationDescriptions"]
    names = {int(k): v for k, v in ia["Id2ObjectNameDict"].items()}
    return names, ia["perFrameAnnotations"]


def frame_record(per_frame, key):
    """(boxes {iid: (x0,y0,w,h)}, colours {iid: (r,g,b)}) of one annotation frame."""
    boxes, colours = {}, {}
    for a in per_frame[str(key)][0]["annotations"]:
        t = a["@type"]
        if t.endswith("BoundingBox2DAnnotation"):
            for v in a["values"]:
                boxes[v["instanceId"]] = tuple(v["origin"]) + tuple(v["dimension"])
        elif t.endswith("InstanceSegmentationAnnotation"):
            for v in a["instances"]:
                colours[v["instanceId"]] = tuple(v["color"][:3])
    return boxes, colours


def seg_to_instances(seg, colours, threshold=None):
    """Segmentation RGB -> instance-id map. Exact colour match if threshold is None, else the nearest
    instance colour within `threshold` RGB distance (lossy video)."""
    h, w, _ = seg.shape
    inst = np.zeros((h, w), np.uint8)
    if not colours:
        return inst
    if threshold is None:
        packed = (seg[..., 0].astype(np.int32) << 16) | (seg[..., 1].astype(np.int32) << 8) | seg[..., 2]
        for iid, c in colours.items():
            inst[packed == ((c[0] << 16) | (c[1] << 8) | c[2])] = iid
        return inst
    ids = list(colours)
    cols = np.array([colours[i] for i in ids], np.float32)
    s = seg.reshape(-1, 3).astype(np.float32)
    best_d = np.full(s.shape[0], np.inf, np.float32)
    best_i = np.zeros(s.shape[0], np.uint8)
    for i, c in zip(ids, cols):
        dd = ((s - c) ** 2).sum(1)
        m = dd < best_d
        best_d[m] = dd[m]
        best_i[m] = i
    best_i[best_d > threshold * threshold] = 0
    return best_i.reshape(h, w)


def targets_from_map(inst, classes):
    """Instance map (H,W) + {iid: class} -> (boxes [K,4] float32 x1,y1,x2,y2 with x2 = max_x+1,
    labels [K] int64, masks [K,H,W] uint8). Instances under MIN_PIXELS pixels are dropped."""
    boxes, labels, masks = [], [], []
    for iid, cls in sorted(classes.items()):
        if cls == 0:
            continue
        m = inst == iid
        if m.sum() < MIN_PIXELS:
            continue
        ys, xs = np.nonzero(m)
        boxes.append([xs.min(), ys.min(), xs.max() + 1, ys.max() + 1])
        labels.append(cls)
        masks.append(m)
    h, w = inst.shape
    if not boxes:
        return np.zeros((0, 4), np.float32), np.zeros((0,), np.int64), np.zeros((0, h, w), np.uint8)
    return (np.array(boxes, np.float32), np.array(labels, np.int64), np.stack(masks).astype(np.uint8))


def decode_video(path, width, height):
    """All frames of a video as uint8 [F,H,W,3] via the ffmpeg CLI."""
    import subprocess
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         check=True, stdout=subprocess.PIPE).stdout
    return np.frombuffer(raw, np.uint8).reshape(-1, height, width, 3)
