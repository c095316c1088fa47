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

# The fluid model's classes (its own model, models/maskrcnn-fluid.onnx; same contract).
FLUID_CLASSES = {
    1: "stick",
    2: "container",
    3: "emitter",
    4: "fluid",
}
FLUID_FLUID = 4  # the class whose instances are split into connected components per frame

# The ball model's classes (its own model, models/maskrcnn-ball.onnx; same contract). Material is
# not a class (elastic and rigid balls share a prefab; a plastic ball differs only by its dent),
# nor is a ramp's side.
BALL_CLASSES = {
    1: "ball",
    2: "floating wall",
    3: "ramp",
    4: "floor piece",
}

# The cloth model's classes (its own model, models/maskrcnn-cloth.onnx; same contract). Colour is
# not a class (the cloth's colour is a random tint that no name carries), nor is a cloth's side.
CLOTH_CLASSES = {
    1: "cloth",
    2: "pillar",
    3: "plate",
}

# Per scenario: class table, number of classes with background, the data root's scenario folder.
SCENARIOS = {
    "rope": {"classes": CLASSES, "num_classes": NUM_CLASSES, "folder": "pulley_group"},
    "fluid": {"classes": FLUID_CLASSES, "num_classes": len(FLUID_CLASSES) + 1, "folder": "fluid_slides"},
    "ball": {"classes": BALL_CLASSES, "num_classes": len(BALL_CLASSES) + 1, "folder": "soft_body"},
    "cloth": {"classes": CLOTH_CLASSES, "num_classes": len(CLOTH_CLASSES) + 1, "folder": "cloth_collision"},
}


def scenario(name):
    """The SCENARIOS entry of `name` (rope, fluid, ball, cloth)."""
    if name not in SCENARIOS:
        raise SystemExit(f"unknown scenario {name!r} (known: {', '.join(SCENARIOS)})")
    return SCENARIOS[name]


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


def fluid_object_of_name(name):
    """(class id, group key) of a fluid-scenario Id2ObjectNameDict name; class 0 = background.

    The five parts of a container ("<C> Container Left Guided Stick", "... Bottom Floor",
    "... Left Vertical Wall", ...) are one container, key "<C> Container"; emitters
    ("<key> Emitter") are each their own object; "<C> Fluid" and "Later Emitted <C> Fluid" are one
    fluid group per colour, key "<C> Fluid" (split into connected components per frame, see
    split_components); "<C> Stick" is a stick. Tank walls, Floor, Ceiling (and anything unknown,
    returned with key None) are background."""
    if " Container " in name or name.endswith(" Container"):
        return 2, name[:name.index(" Container")] + " Container"
    if name.endswith(" Emitter"):
        return 3, name
    if name.endswith(" Fluid"):
        base = name[len("Later Emitted "):] if name.startswith("Later Emitted ") else name
        return FLUID_FLUID, base
    if name.endswith(" Stick"):
        return 1, name
    if name in ("Left Vertical Wall", "Right Vertical Wall", "Floor", "Ceiling"):
        return 0, name
    return 0, None


def fluid_groups(names):
    """Generator instance ids -> target ids of a fluid video.

    Returns (lut [256] uint8: generator id -> group id, 0 = background; classes [256] int64:
    group id -> class; fluid_ids: the group ids of the per-colour fluid unions, to be split into
    components; first_free: the first id free for fluid components; unknown: names not understood).
    Group ids 1.. are the objects in order of their first generator id."""
    lut = np.zeros(256, np.uint8)
    classes = np.zeros(256, np.int64)
    keys, unknown = {}, []
    for iid in sorted(names):
        cls, key = fluid_object_of_name(names[iid])
        if key is None:
            unknown.append(names[iid])
        if cls == 0:
            continue
        if key not in keys:
            keys[key] = len(keys) + 1
            classes[keys[key]] = cls
        lut[iid] = keys[key]
    fluid_ids = [g for k, g in keys.items() if classes[g] == FLUID_FLUID]
    first_free = len(keys) + 1
    classes[first_free:] = FLUID_FLUID  # components get ids first_free..255
    return lut, classes, fluid_ids, first_free, unknown


def ball_class_of_name(name):
    """Class id of a ball-scenario Id2ObjectNameDict name: "<C> Ball" 1, "<C> Floating Wall" 2,
    "Right Ramp" / "Left Ramp" 3, "Floor Piece 1st" (2nd, 3rd) 4; 0 for anything else."""
    if name.endswith(" Ball"):
        return 1
    if name.endswith(" Floating Wall"):
        return 2
    if name in ("Right Ramp", "Left Ramp"):
        return 3
    if name.startswith("Floor Piece"):
        return 4
    return 0


def ball_groups(names):
    """Generator instance ids -> target ids of a ball video, in the shape of fluid_groups: every
    named object is its own instance (its generator id kept), nothing is split into components.
    Returns (lut, classes, fluid_ids = [], first_free, unknown names)."""
    lut = np.zeros(256, np.uint8)
    classes = np.zeros(256, np.int64)
    unknown = []
    for iid, name in names.items():
        cls = ball_class_of_name(name)
        if cls == 0:
            unknown.append(name)
            continue
        lut[iid] = iid
        classes[iid] = cls
    return lut, classes, [], max(names, default=0) + 1, unknown


def cloth_class_of_name(name):
    """Class id of a cloth-scenario Id2ObjectNameDict name: "Cloth (Left)" / "Cloth (Right)" 1,
    "<C> Pillar" 2, "<C> Plate" 3; 0 for anything else ("Table", a "<C> Cube" tower layer)."""
    if name in ("Cloth (Left)", "Cloth (Right)"):
        return 1
    if name.endswith(" Pillar"):
        return 2
    if name.endswith(" Plate"):
        return 3
    return 0


def cloth_groups(names):
    """Generator instance ids -> target ids of a cloth video, in the shape of ball_groups: every
    cloth, pillar and plate is its own instance (its generator id kept). The table and cubes (a
    tower layer not merged into a pillar, practically never written) are background and not
    reported; other names are background and reported as unknown."""
    lut = np.zeros(256, np.uint8)
    classes = np.zeros(256, np.int64)
    unknown = []
    for iid, name in names.items():
        cls = cloth_class_of_name(name)
        if cls == 0:
            if name != "Table" and not name.endswith(" Cube"):
                unknown.append(name)
            continue
        lut[iid] = iid
        classes[iid] = cls
    return lut, classes, [], max(names, default=0) + 1, unknown


def dilate3(m):
    """3x3 binary dilation (bool HxW), zero outside the image."""
    p = np.pad(m, 1)
    h, w = m.shape
    out = np.zeros_like(m)
    for dy in range(3):
        for dx in range(3):
            out |= p[dy:dy + h, dx:dx + w]
    return out


def components8(m):
    """8-connected components of a bool HxW mask: int32 label map (0 = outside, 1.. components
    numbered in raster order of their first pixel) and the number of components. Union-find over
    the horizontal runs of each row (numpy + Python only)."""
    h, w = m.shape
    parent = []
    runs = []  # per row: (starts, ends exclusive, run ids)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for y in range(h):
        d = np.diff(np.concatenate([[0], m[y].astype(np.int8), [0]]))
        s, e = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
        ids = list(range(len(parent), len(parent) + len(s)))
        parent.extend(ids)
        if y and len(s) and len(runs[-1][0]):
            ps, pe, pids = runs[-1]
            j = 0
            for k in range(len(s)):
                # previous-row runs touching [s-1, e] (8-connectivity)
                while j < len(ps) and pe[j] < s[k]:
                    j += 1
                jj = j
                while jj < len(ps) and ps[jj] <= e[k]:
                    a, b = find(ids[k]), find(pids[jj])
                    if a != b:
                        parent[max(a, b)] = min(a, b)
                    jj += 1
        runs.append((s, e, ids))
    labels = np.zeros((h, w), np.int32)
    roots = {}
    for y, (s, e, ids) in enumerate(runs):
        for k in range(len(s)):
            r = find(ids[k])
            if r not in roots:
                roots[r] = len(roots) + 1
            labels[y, s[k]:e[k]] = roots[r]
    return labels, len(roots)


def split_components(g, fluid_ids, first_free, min_pixels=MIN_PIXELS, join=1):
    """Replaces each per-colour fluid union (ids fluid_ids in the group map g, uint8) by its
    connected components: 8-connectivity after a (2*join+1)-square dilation (droplets within
    2*join pixels join); with join 1 a component's pixels are the undilated union inside it, with
    join > 1 they are its closing (dilation then erosion by the same square, inside the component:
    the gaps between nearby droplets filled, a solid region the 28x28 mask head can draw; the pixels
    are refined by colour at answer time). Components of at least min_pixels pixels get ids
    first_free, first_free+1, ... (colour by colour, raster order), smaller ones become background.
    Returns the new map and the number of components."""
    out = g.copy()
    masks = [g == f for f in fluid_ids]
    for m in masks:
        out[m] = 0
    nxt = first_free
    for m in masks:
        if not m.any():
            continue
        grown = m
        for _ in range(join):
            grown = dilate3(grown)
        labels, n = components8(grown)
        if join > 1:
            shrunk = ~grown
            for _ in range(join):
                shrunk = dilate3(shrunk)
            closed = ~shrunk | m
        for c in range(1, n + 1):
            comp = (closed if join > 1 else m) & (labels == c)
            if (m & comp).sum() < min_pixels:
                continue
            if nxt > 255:
                raise ValueError("more than 255 instances in a frame")
            # Solid objects drawn over the fluid keep their pixels.
            comp &= (out == 0) | m
            out[comp] = nxt
            nxt += 1
    return out, nxt - first_free


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


def decode_video(path, width, height, passthrough=False):
    """All frames of a video as uint8 [F,H,W,3] via the ffmpeg CLI (passthrough: one output frame
    per coded frame, `-fps_mode passthrough`, as the Rust side decodes)."""
    import subprocess
    extra = ["-nostdin", "-fps_mode", "passthrough"] if passthrough else []
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path] + extra + ["-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         check=True, stdout=subprocess.PIPE).stdout
    return np.frombuffer(raw, np.uint8).reshape(-1, height, width, 3)
