"""The experiment behind `perception::closer`: how often the detector names the class of each
pulley (or load) right from the whole 1080p frame (box-averaged to 480x270), from a 480x270
window of the frame box-averaged to 960x540 centred on the object (twice the scale), and from the
two summed, over a few frames per video.

  python closer_look.py MODEL.onnx DATA_ROOT [--frames 0,30,60] [--loads] [--limit N]

DATA_ROOT holds pulley_group/<id>/{output_Full.mp4,outputs.json} (generated 1920x1080 videos).
Per object, each look votes with the detector's score for the class of the detection that
overlaps the annotated box most (IoU >= 0.5, among the rival classes); the class with the
largest sum wins; two other weightings are counted too: `window_twice` (the window's votes
count double) and `window_first` (the window's vote, the whole frame's only where the window has
none). Prints the counts right per look and the objects each look got wrong.
Needs numpy, onnxruntime and ffmpeg on PATH.
"""
import argparse
import glob
import os
import subprocess
from collections import defaultdict

import numpy as np
import onnxruntime as ort

from common import class_of_name, frame_record, load_annotations

PULLEYS = (5, 6, 7, 8)
LOADS = (1, 2)


def decode(path, index):
    raw = subprocess.run(
        ["ffmpeg", "-loglevel", "error", "-i", path, "-vf", f"select=eq(n\\,{index})",
         "-vframes", "1", "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
        capture_output=True, check=True).stdout
    return np.frombuffer(raw, np.uint8).reshape(1080, 1920, 3).astype(np.float64)


def shrink(img, factor):
    h, w, _ = img.shape
    return img.reshape(h // factor, factor, w // factor, factor, 3).mean(axis=(1, 3)).round()


def iou(a, b):
    w = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    h = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    inter = w * h
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def best(outputs, box, rivals):
    """(class, score) of the rival-class detection overlapping `box` most; (0, 0) if none."""
    found = (0, 0.0, 0.5)
    for b, label, score in zip(outputs["boxes"], outputs["labels"], outputs["scores"]):
        overlap = iou(b, box)
        if int(label) in rivals and overlap >= found[2]:
            found = (int(label), float(score), overlap)
    return found[0], found[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("data")
    ap.add_argument("--frames", default="0,30,60")
    ap.add_argument("--loads", action="store_true", help="loads (cube/sphere) instead of pulleys")
    ap.add_argument("--limit", type=int, default=0, help="only the first N videos")
    args = ap.parse_args()
    rivals = LOADS if args.loads else PULLEYS
    options = ort.SessionOptions()
    options.intra_op_num_threads = 1
    session = ort.InferenceSession(args.model, options)
    names_out = [o.name for o in session.get_outputs()]

    def detect(img):
        x = img.transpose(2, 0, 1).astype(np.float32) / 255.0
        return dict(zip(names_out, session.run(None, {"images_tensors": x})))

    videos = sorted(glob.glob(os.path.join(args.data, "pulley_group", "*", "")),
                    key=lambda p: int(os.path.basename(p.rstrip("/"))))
    if args.limit:
        videos = videos[: args.limit]
    right = defaultdict(int)
    total = 0
    for video in videos:
        names, per_frame = load_annotations(os.path.join(video, "outputs.json"))
        votes = defaultdict(lambda: {"whole": defaultdict(float), "window": defaultdict(float)})
        for index in (int(f) for f in args.frames.split(",")):
            boxes, _ = frame_record(per_frame, index + 1)
            img = decode(os.path.join(video, "output_Full.mp4"), index)
            whole, half = detect(shrink(img, 4)), shrink(img, 2)
            for iid, (x0, y0, w, h) in boxes.items():
                if class_of_name(names.get(iid, "")) not in rivals:
                    continue
                label, score = best(whole, [x0 / 4, y0 / 4, (x0 + w) / 4, (y0 + h) / 4], rivals)
                votes[iid]["whole"][label] += score
                cx, cy = (x0 + w / 2) / 2, (y0 + h / 2) / 2
                wx = int(np.clip(round(cx - 240), 0, 480))
                wy = int(np.clip(round(cy - 135), 0, 270))
                window = detect(half[wy:wy + 270, wx:wx + 480])
                box = [x0 / 2 - wx, y0 / 2 - wy, (x0 + w) / 2 - wx, (y0 + h) / 2 - wy]
                label, score = best(window, box, rivals)
                votes[iid]["window"][label] += score
        for iid, looks in votes.items():
            truth = class_of_name(names[iid])
            both = defaultdict(float)
            for look in looks.values():
                for label, score in look.items():
                    both[label] += score
            total += 1
            double = defaultdict(float)
            for label, score in looks["whole"].items():
                double[label] += score
            for label, score in looks["window"].items():
                double[label] += 2 * score
            window_first = {k: v for k, v in looks["window"].items() if k} or looks["whole"]
            for name, tally in (("whole", looks["whole"]), ("window", looks["window"]), ("both", both),
                                ("window_twice", double), ("window_first", window_first)):
                tally = {k: v for k, v in tally.items() if k}
                pick = max(tally, key=tally.get) if tally else 0
                right[name] += pick == truth
                if pick != truth:
                    print(f"{name:6s} video {os.path.basename(video.rstrip('/'))}: {names[iid]} read as class {pick}")
    print({"objects": total, **{f"{k}_right": v for k, v in right.items()}})


if __name__ == "__main__":
    main()
