"""Box and mask AP@0.5 of an exported ONNX model (onnxruntime, 1 intra-op thread) on 480x270 caches.

  python evaluate.py MODEL.onnx --heldout CACHE_DIR --real REAL_NPZ [--real-min-key 101] [--json OUT.json]
  python evaluate.py MODEL.onnx --scenario fluid --heldout CACHE_DIR [--heldout-mp4 CACHE_DIR] [--json OUT.json]
  python evaluate.py MODEL.onnx --scenario ball --heldout CACHE_DIR [--heldout-mp4 CACHE_DIR] [--json OUT.json]
  python evaluate.py MODEL.onnx --scenario cloth --heldout CACHE_DIR [--heldout-mp4 CACHE_DIR] [--json OUT.json]

AP: per class, detections of all images sorted by score, greedy matching to unmatched ground truth
of the same class at IoU >= 0.5, all-point interpolated precision/recall area (VOC 2010+ style).
Masks are pasted with torchvision's paste_masks_in_image (padding 1) and thresholded at 0.5.
Ground truth: instances of the downscaled instance map with >= 6 pixels. Only detections above the
model's baked-in score threshold exist, so recall is capped by it.
--scenario fluid (ball, cloth) scores the fluid (ball, cloth) classes; --heldout-mp4 is a cache of
the same held-out videos with the RGB decoded from output_Full.mp4 (prep_data.py --rgb mp4), scored as heldout_generated_mp4.
"""
import argparse
import glob
import json
import os
import time

import numpy as np
import onnxruntime as ort
import torch
from torchvision.models.detection.roi_heads import paste_masks_in_image

from common import CLASSES, scenario, targets_from_map


def box_iou(a, b):
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)))
    x1 = np.maximum(a[:, None, 0], b[None, :, 0]); y1 = np.maximum(a[:, None, 1], b[None, :, 1])
    x2 = np.minimum(a[:, None, 2], b[None, :, 2]); y2 = np.minimum(a[:, None, 3], b[None, :, 3])
    inter = np.clip(x2 - x1, 0, None) * np.clip(y2 - y1, 0, None)
    aa = (a[:, 2] - a[:, 0]) * (a[:, 3] - a[:, 1]); ab = (b[:, 2] - b[:, 0]) * (b[:, 3] - b[:, 1])
    return inter / (aa[:, None] + ab[None, :] - inter)


def mask_iou(a, b):
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)))
    a = a.reshape(len(a), -1).astype(np.float32); b = b.reshape(len(b), -1).astype(np.float32)
    inter = a @ b.T
    return inter / (a.sum(1)[:, None] + b.sum(1)[None, :] - inter)


def ap_of(records, n_gt):
    """records: list of (score, is_tp)."""
    if n_gt == 0:
        return None
    if not records:
        return 0.0
    records.sort(key=lambda r: -r[0])
    tp = np.cumsum([r[1] for r in records]); fp = np.cumsum([1 - r[1] for r in records])
    rec = tp / n_gt; prec = tp / np.maximum(tp + fp, 1e-9)
    mrec = np.concatenate([[0], rec, [1]]); mpre = np.concatenate([[0], prec, [0]])
    for i in range(len(mpre) - 2, -1, -1):
        mpre[i] = max(mpre[i], mpre[i + 1])
    idx = np.where(mrec[1:] != mrec[:-1])[0]
    return float(((mrec[idx + 1] - mrec[idx]) * mpre[idx + 1]).sum())


class Evaluator:
    def __init__(self, classes=CLASSES):
        self.classes = classes
        self.rec = {"box": {c: [] for c in classes}, "mask": {c: [] for c in classes}}
        self.ngt = {c: 0 for c in classes}
        self.images = 0
        self.seconds = 0.0

    def add(self, out, gt_boxes, gt_labels, gt_masks):
        self.images += 1
        boxes, labels, scores, masks = out["boxes"], out["labels"], out["scores"], out["masks"]
        if len(boxes):
            pasted = paste_masks_in_image(torch.from_numpy(masks), torch.from_numpy(boxes),
                                          gt_masks.shape[1:], padding=1).numpy()[:, 0] > 0.5
        else:
            pasted = np.zeros((0,) + gt_masks.shape[1:], bool)
        for c in self.classes:
            g = gt_labels == c
            self.ngt[c] += int(g.sum())
            d = np.where(labels == c)[0]
            d = d[np.argsort(-scores[d], kind="stable")]
            for kind, iou in (("box", box_iou(boxes[d], gt_boxes[g])), ("mask", mask_iou(pasted[d], gt_masks[g]))):
                used = np.zeros(g.sum(), bool)
                for j in range(len(d)):
                    tp = 0
                    if iou.shape[1]:
                        cand = np.where(~used, iou[j], -1)
                        k = int(cand.argmax())
                        if cand[k] >= 0.5:
                            used[k] = True
                            tp = 1
                    self.rec[kind][c].append((float(scores[d[j]]), tp))

    def summary(self):
        res = {"images": self.images, "seconds_per_image": round(self.seconds / max(self.images, 1), 3),
               "gt_instances": {self.classes[c]: n for c, n in self.ngt.items()}}
        for kind in ("box", "mask"):
            per = {self.classes[c]: ap_of(list(self.rec[kind][c]), self.ngt[c]) for c in self.classes}
            vals = [v for v in per.values() if v is not None]
            res[f"{kind}_ap50"] = {k: (round(v, 4) if v is not None else None) for k, v in per.items()}
            res[f"{kind}_map50"] = round(float(np.mean(vals)), 4) if vals else None
        return res


def run(sess, img):
    x = img.transpose(2, 0, 1).astype(np.float32) / 255.0
    names = [o.name for o in sess.get_outputs()]
    return dict(zip(names, sess.run(None, {"images_tensors": x})))


def eval_items(sess, items, classes=CLASSES):
    ev = Evaluator(classes)
    for img, inst, cls in items:
        classes = {iid: int(cls[iid]) for iid in np.unique(inst) if iid != 0}
        b, l, m = targets_from_map(inst, classes)
        t = time.time()
        out = run(sess, img)
        ev.seconds += time.time() - t
        ev.add(out, b, l, m.astype(bool))
    return ev.summary()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("--heldout")
    ap.add_argument("--heldout-every", type=int, default=1, help="use every n-th cached frame")
    ap.add_argument("--real")
    ap.add_argument("--real-min-key", type=int, default=101)
    ap.add_argument("--json")
    ap.add_argument("--scenario", default="rope", choices=["rope", "fluid", "ball", "cloth"])
    ap.add_argument("--heldout-mp4", help="fluid, ball, cloth: the held-out videos with their RGB from the mp4")
    a = ap.parse_args()
    classes = scenario(a.scenario)["classes"]
    torch.set_num_threads(1)
    so = ort.SessionOptions()
    so.intra_op_num_threads = 1
    sess = ort.InferenceSession(a.model, so, providers=["CPUExecutionProvider"])
    res = {"onnxruntime": ort.__version__, "intra_op_threads": 1}
    for name, cache in (("heldout_generated", a.heldout), ("heldout_generated_mp4", a.heldout_mp4)):
        if not cache:
            continue
        items, vids = [], []
        for p in sorted(glob.glob(os.path.join(cache, "*.npz"))):
            d = np.load(p)
            vids.append(os.path.basename(p)[:-4])
            for i in range(0, len(d["imgs"]), a.heldout_every):
                items.append((d["imgs"][i], d["inst"][i], d["classes"]))
        res[name] = eval_items(sess, items, classes)
        res[name]["videos"] = vids
        print(json.dumps(res[name]), flush=True)
    if a.real:
        d = np.load(a.real)
        sel = [i for i, k in enumerate(d["keys"]) if k >= a.real_min_key]
        res["real_frames"] = eval_items(sess, [(d["imgs"][i], d["inst"][i], d["classes"]) for i in sel], classes)
        res["real_frames"]["keys"] = [int(d["keys"][sel[0]]), int(d["keys"][sel[-1]])]
        print(json.dumps(res["real_frames"]), flush=True)
    if a.json:
        json.dump(res, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
