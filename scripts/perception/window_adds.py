"""The experiment behind `perception::closer::find_missed`: which annotated objects (not ropes)
the detector misses on the whole 1080p frame (box-averaged to 480x270), and whether a 480x270
window of the frame box-averaged to 960x540 (twice the scale) centred on the missed object finds
it, with which class and score; also what else such a window finds that overlaps no annotated
object (what an addition would get wrong).

  python window_adds.py MODEL.onnx DATA_ROOT [--frames 0,30,60]

DATA_ROOT holds pulley_group/<id>/{output_Full.mp4,outputs.json} (generated 1920x1080 videos).
An object counts as found by the whole frame when any detection of a class other than rope
overlaps its annotated box with IoU >= 0.5. Prints each miss with the window's detections on it
(class id, score), then the counts. Needs numpy, onnxruntime and ffmpeg on PATH.
"""
import argparse
import glob
import os
from collections import defaultdict

import numpy as np
import onnxruntime as ort

from closer_look import decode, iou, shrink
from common import class_of_name, frame_record, load_annotations

ROPE = 3


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("data")
    ap.add_argument("--frames", default="0,30,60")
    args = ap.parse_args()
    options = ort.SessionOptions()
    options.intra_op_num_threads = 1
    session = ort.InferenceSession(args.model, options)
    names_out = [o.name for o in session.get_outputs()]

    def detect(img):
        x = img.transpose(2, 0, 1).astype(np.float32) / 255.0
        return dict(zip(names_out, session.run(None, {"images_tensors": x})))

    def found_in(outputs, scale, dx, dy):
        """(box in 1080p pixels, class, score) of the non-rope detections."""
        return [([(b[0] + dx) * scale, (b[1] + dy) * scale, (b[2] + dx) * scale, (b[3] + dy) * scale],
                 int(label), float(score))
                for b, label, score in zip(outputs["boxes"], outputs["labels"], outputs["scores"])
                if int(label) != ROPE]

    stats = defaultdict(int)
    videos = sorted(glob.glob(os.path.join(args.data, "pulley_group", "*", "")),
                    key=lambda p: int(os.path.basename(p.rstrip("/"))))
    for video in videos:
        video_id = os.path.basename(video.rstrip("/"))
        names, per_frame = load_annotations(os.path.join(video, "outputs.json"))
        for index in (int(f) for f in args.frames.split(",")):
            boxes, _ = frame_record(per_frame, index + 1)
            img = decode(os.path.join(video, "output_Full.mp4"), index)
            whole = found_in(detect(shrink(img, 4)), 4, 0, 0)
            half = shrink(img, 2)
            objects = {iid: [x0, y0, x0 + w, y0 + h] for iid, (x0, y0, w, h) in boxes.items()
                       if class_of_name(names.get(iid, "")) not in (0, ROPE)}
            for iid, box in objects.items():
                stats["objects"] += 1
                if any(iou(b, box) >= 0.5 for b, _, _ in whole):
                    continue
                stats["missed_by_whole_frame"] += 1
                cx, cy = (box[0] + box[2]) / 4, (box[1] + box[3]) / 4
                wx = int(np.clip(round(cx - 240), 0, 480))
                wy = int(np.clip(round(cy - 135), 0, 270))
                window = found_in(detect(half[wy:wy + 270, wx:wx + 480]), 2, wx, wy)
                hits = [(label, round(score, 2)) for b, label, score in window if iou(b, box) >= 0.5]
                right = [h for h in hits if h[0] == class_of_name(names[iid])]
                stats["window_found"] += bool(hits)
                stats["window_found_right_class"] += bool(right)
                print(f"video {video_id} frame {index}: {names[iid]} missed by the whole frame; window {hits}")
                for b, label, score in window:
                    if all(iou(b, other) < 0.3 for other in objects.values()):
                        stats["window_detections_on_no_object"] += 1
                        print(f"   on no object: class {label} score {score:.2f}")
    print(dict(stats))


if __name__ == "__main__":
    main()
