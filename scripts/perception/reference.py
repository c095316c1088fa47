"""Reference data for the Rust tests.

  python reference.py MODEL.onnx REAL_NPZ PNG_OUT JSON_OUT [--key 60]

PNG_OUT: real video frame with annotation key 60 (0-based mp4 frame 59) downscaled 1920x1080 -> 480x270
by an exact 4x4 box average rounded half up (the REAL_NPZ cache from prep_data.py holds exactly that), RGB.
JSON_OUT: onnxruntime outputs of MODEL on that PNG (uint8 / 255 as float32, CHW), intra-op threads 1,
plus torchvision paste_masks_in_image(masks, boxes, (270, 480), padding=1) > 0.5 as [y, x_start, x_end) runs.
"""
import argparse
import json

import numpy as np
import onnxruntime as ort
import torch
from PIL import Image
from torchvision.models.detection.roi_heads import paste_masks_in_image


def runs_of(mask):
    out = []
    for y in range(mask.shape[0]):
        row = np.concatenate([[False], mask[y], [False]])
        d = np.flatnonzero(row[1:] != row[:-1])
        for s, e in zip(d[0::2], d[1::2]):
            out.append([int(y), int(s), int(e)])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("real")
    ap.add_argument("png")
    ap.add_argument("json")
    ap.add_argument("--key", type=int, default=60)
    a = ap.parse_args()
    torch.set_num_threads(1)
    d = np.load(a.real)
    i = int(np.flatnonzero(d["keys"] == a.key)[0])
    Image.fromarray(d["imgs"][i], "RGB").save(a.png, optimize=True)
    img = np.asarray(Image.open(a.png).convert("RGB"))
    assert (img == d["imgs"][i]).all()
    x = (img.astype(np.float32) / np.float32(255.0)).transpose(2, 0, 1).copy()
    so = ort.SessionOptions()
    so.intra_op_num_threads = 1
    sess = ort.InferenceSession(a.model, so, providers=["CPUExecutionProvider"])
    names = [o.name for o in sess.get_outputs()]
    out = dict(zip(names, sess.run(None, {"images_tensors": x})))
    h, w = img.shape[:2]
    pasted = paste_masks_in_image(torch.from_numpy(out["masks"]), torch.from_numpy(out["boxes"]), (h, w),
                                  padding=1).numpy()[:, 0] > 0.5
    ref = {
        "description": f"onnxruntime outputs of the model on the real rope video frame key {a.key} "
                       f"(mp4 frame {a.key - 1}, 0-based) at {w}x{h}; input uint8/255 float32 CHW RGB",
        "onnxruntime_version": ort.__version__,
        "intra_op_threads": 1,
        "input_shape": [3, h, w],
        "boxes": out["boxes"].tolist(),
        "labels": out["labels"].tolist(),
        "scores": out["scores"].tolist(),
        "masks": [m.reshape(-1).tolist() for m in out["masks"]],
        "pasted_masks_note": "paste_masks_in_image(masks, boxes, (270, 480), padding=1) > 0.5, runs [y, x_start, x_end_exclusive]",
        "pasted_masks": [runs_of(m) for m in pasted],
    }
    json.dump(ref, open(a.json, "w"))
    print(len(out["scores"]), "detections", out["labels"].tolist(), [round(s, 3) for s in out["scores"].tolist()])


if __name__ == "__main__":
    main()
