"""Export a checkpoint to ONNX (legacy exporter, opset 17), raw 28x28 masks, baked-in thresholds.

  python export.py CKPT.pt OUT.onnx [--score-thresh 0.3] [--nms 0.5] [--detections 24] [--check REAL_NPZ]
                   [--scenario fluid|ball|cloth]
"""
import argparse

import numpy as np
import onnxruntime as ort
import torch

from common import IN_H, IN_W, scenario
from model import build_model


def load(ckpt, **kw):
    model = build_model(paste_masks=False, **kw)
    model.load_state_dict(torch.load(ckpt, map_location="cpu", weights_only=False)["model"])
    model.eval()
    return model


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ckpt")
    ap.add_argument("out")
    ap.add_argument("--score-thresh", type=float, default=0.3)
    ap.add_argument("--nms", type=float, default=0.5)
    ap.add_argument("--detections", type=int, default=24)
    ap.add_argument("--check", help="an .npz cache whose first image is the trace/compare input")
    ap.add_argument("--check-frame", type=int, default=0, help="the image of --check to use")
    ap.add_argument("--scenario", default="rope", choices=["rope", "fluid", "ball", "cloth"],
                    help="the class table the checkpoint was trained with (train.py --scenario)")
    a = ap.parse_args()
    torch.set_num_threads(1)
    model = load(a.ckpt, score_thresh=a.score_thresh, nms_thresh=a.nms, detections=a.detections,
                 num_classes=scenario(a.scenario)["num_classes"])
    torch.manual_seed(0)
    example = torch.rand(3, IN_H, IN_W)
    if a.check:
        example = torch.from_numpy(np.load(a.check)["imgs"][a.check_frame].transpose(2, 0, 1).astype(np.float32) / 255.0)
    with torch.no_grad():
        torch.onnx.export(model, ([example],), a.out, dynamo=False, opset_version=17,
                          input_names=["images_tensors"], output_names=["boxes", "labels", "scores", "masks"],
                          dynamic_axes={"images_tensors": [1, 2], "boxes": [0], "labels": [0], "scores": [0],
                                        "masks": [0]})
        ref = model([example])[0]
    so = ort.SessionOptions()
    so.intra_op_num_threads = 1
    sess = ort.InferenceSession(a.out, so, providers=["CPUExecutionProvider"])
    print("inputs", [(i.name, i.shape, i.type) for i in sess.get_inputs()])
    out = dict(zip([o.name for o in sess.get_outputs()], sess.run(None, {"images_tensors": example.numpy()})))
    print({k: (v.shape, v.dtype) for k, v in out.items()})
    print("torch dets", len(ref["scores"]), "ort dets", len(out["scores"]))
    if len(ref["scores"]) == len(out["scores"]) and len(out["scores"]):
        print("max |d| boxes", np.abs(ref["boxes"].numpy() - out["boxes"]).max(),
              "scores", np.abs(ref["scores"].numpy() - out["scores"]).max(),
              "masks", np.abs(ref["masks"].numpy() - out["masks"]).max(),
              "labels equal", bool((ref["labels"].numpy() == out["labels"]).all()))


if __name__ == "__main__":
    main()
