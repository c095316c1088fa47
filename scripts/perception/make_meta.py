"""Write models/maskrcnn-rope.json from a checkpoint's metadata and evaluate.py's JSON.

  python make_meta.py CKPT.json EVAL.json MODEL.onnx OUT.json --videos DATA [--score-thresh 0.3 --nms 0.5 --detections 24]
  python make_meta.py CKPT.json EVAL.json MODEL.onnx OUT.json --videos DATA --scenario fluid --detections 64
  python make_meta.py CKPT.json EVAL.json MODEL.onnx OUT.json --videos DATA --scenario ball
  python make_meta.py CKPT.json EVAL.json MODEL.onnx OUT.json --videos DATA --scenario cloth --eval-randomized EVAL_RAND.json

DATA is the directory holding the generated data roots the caches were made from (train-rand/,
train-rel/): every training video is listed with the SHA-256 of its outputs.json, so a test can
check that the real video is not among them. For fluid (models/maskrcnn-fluid.json) DATA holds
fluid-train-rand/ and fluid-train-rel/ (caches named like their data roots), for ball
(models/maskrcnn-ball.json) ball-train-rand/ and ball-train-rel/, for cloth
(models/maskrcnn-cloth.json) cloth-train-rand/ and cloth-train-rel/. --eval-randomized adds
evaluate.py's JSON of the same held-out scenes drawn with randomised appearance to the metrics
(heldout_generated_randomized, heldout_generated_randomized_mp4).
"""
import argparse
import hashlib
import json
import os

from common import IN_H, IN_W, scenario

GENERATE = [
    "contphy-eval generate --scenario rope --videos 48 --seed 3101 --out train-rand --frames png "
    "--resolution 960x540 --jobs 1 --quiet --appearance randomized",
    "contphy-eval generate --scenario rope --videos 24 --seed 3102 --out train-rel --frames png "
    "--resolution 960x540 --jobs 1 --quiet",
    "contphy-eval generate --scenario rope --videos 12 --seed 909 --out heldout-rope --frames png "
    "--resolution 960x540 --jobs 1 --quiet",
]

FLUID_GENERATE = [
    "contphy-eval generate --scenario fluid --videos 24 --seed 3201 --out fluid-train-rand --frames both "
    "--resolution 480x270 --jobs 1 --quiet --appearance randomized",
    "contphy-eval generate --scenario fluid --videos 12 --seed 3202 --out fluid-train-rel --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
    "contphy-eval generate --scenario fluid --videos 8 --seed 11 --out fluid-tune11 --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
]

BALL_GENERATE = [
    "contphy-eval generate --scenario ball --videos 24 --seed 3301 --out ball-train-rand --frames both "
    "--resolution 480x270 --jobs 1 --quiet --appearance randomized",
    "contphy-eval generate --scenario ball --videos 12 --seed 3302 --out ball-train-rel --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
    "contphy-eval generate --scenario ball --videos 8 --seed 3303 --out ball-heldout3303 --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
]

CLOTH_GENERATE = [
    "contphy-eval generate --scenario cloth --videos 24 --seed 3401 --out cloth-train-rand --frames both "
    "--resolution 480x270 --jobs 1 --quiet --appearance randomized",
    "contphy-eval generate --scenario cloth --videos 12 --seed 3402 --out cloth-train-rel --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
    "contphy-eval generate --scenario cloth --videos 8 --seed 3403 --out cloth-heldout3403 --frames both "
    "--resolution 480x270 --jobs 1 --quiet",
    "contphy-eval generate --scenario cloth --videos 8 --seed 3403 --out cloth-heldout3403-rand --frames both "
    "--resolution 480x270 --jobs 1 --quiet --appearance randomized",
]

# The scenario-specific sentences of the description (rope: those of models/maskrcnn-rope.json).
TEXT = {
    "rope": {
        "generate": GENERATE,
        "randomised": "rope strands, shadows, noise and blur",
        "mix": "train-rand (randomised appearance) and train-rel (the release's look), each as the whole "
               "frame box-averaged to 480x270 (every 3rd frame) and as 480x270 windows of the 960x540 frame "
               "round the objects (zoom-rand, zoom-rel: every 6th frame; the camera twice as close), sampled "
               "uniformly by frame",
        "frames_note": "every 3rd frame of each video (offset video_id % 3); 960x540 PNG -> 480x270 by "
                       "2x2 box average (round half up); masks: an instance owns an output pixel if it "
                       "covers >= 2 of its 4 source pixels; instances under 6 pixels dropped",
        "held_out": "the release's real video: a test only (metrics.real_frames), never a training input",
    },
    "fluid": {
        "generate": FLUID_GENERATE,
        "randomised": "shadows, noise and blur",
        "mix": "fluid-train-rand (randomised appearance) and fluid-train-rel (the release's look), the whole "
               "480x270 frame (every 5th frame), sampled uniformly by frame",
        "frames_note": "every 5th frame of each video (offset video_id % 5), 480x270 as generated; RGB from the "
                       "PNG on even cached frames and from output_Full.mp4 (ffmpeg, rgb24, -fps_mode passthrough) "
                       "on odd ones, so that half the frames carry the compression of the evaluated videos; masks "
                       "from the exact PNG segmentation colours: the five parts of a container are one container, "
                       "each stick and emitter its own instance, the fluids of one colour (<C> Fluid and Later "
                       "Emitted <C> Fluid) united and split into connected components (8-connectivity after a 3x3 "
                       "dilation; a component's mask is the undilated union inside it) in stage 1, and in stage 2 "
                       "(prep_data.py --fluid-join 3) the fluids of all colours united into regions (drops within "
                       "6 pixels joined, the gaps closed by a 7x7 closing; the colour of each pixel names its fluid "
                       "at answer time); tank walls, floor and ceiling are background; instances under 6 pixels "
                       "dropped",
        "held_out": "fluid-tune11 (seed 11, videos 0-5): evaluation only (metrics; every 10th frame, RGB from the "
                    "PNG and, as heldout_generated_mp4, from the mp4; fluid targets as in stage 2); the test set "
                    "(seed 2026) is never used",
    },
    "ball": {
        "generate": BALL_GENERATE,
        "randomised": "shadows, noise and blur",
        "mix": "ball-train-rand (randomised appearance) and ball-train-rel (the release's look), the whole "
               "480x270 frame (every 5th frame), sampled uniformly by frame",
        "frames_note": "every 5th frame of each video (offset video_id % 5), 480x270 as generated; RGB from the "
                       "PNG on even cached frames and from output_Full.mp4 (ffmpeg, rgb24, -fps_mode passthrough) "
                       "on odd ones, so that half the frames carry the compression of the evaluated videos; masks "
                       "from the exact PNG segmentation colours, each object its own instance: <C> Ball a ball, "
                       "<C> Floating Wall a floating wall, Right Ramp and Left Ramp a ramp, Floor Piece 1st/2nd/3rd "
                       "a floor piece; the stadium behind them is not segmented (background); instances under "
                       "6 pixels dropped (a ball in a pit)",
        "held_out": "ball-heldout3303 (seed 3303, 8 videos): evaluation only (metrics; every 10th frame, RGB from "
                    "the PNG and, as heldout_generated_mp4, from the mp4); the test seeds (2026, 100) are never used",
    },
    "cloth": {
        "generate": CLOTH_GENERATE,
        "randomised": "shadows, noise and blur",
        "mix": "cloth-train-rand (randomised appearance) and cloth-train-rel (the release's look), the whole "
               "480x270 frame (every 5th frame), sampled uniformly by frame",
        "frames_note": "every 5th frame of each video (offset video_id % 5), 480x270 as generated; RGB from the "
                       "PNG on even cached frames and from output_Full.mp4 (ffmpeg, rgb24, -fps_mode passthrough) "
                       "on odd ones, so that half the frames carry the compression of the evaluated videos; masks "
                       "from the exact PNG segmentation colours, each object its own instance: Cloth (Left) and "
                       "Cloth (Right) a cloth, <C> Pillar a pillar, <C> Plate a plate; the table (and a <C> Cube, "
                       "practically never written) is background, the room behind is not segmented; instances "
                       "under 6 pixels dropped (a box hidden under a cloth)",
        "held_out": "cloth-heldout3403 (seed 3403, 8 videos): evaluation only (metrics; every 10th frame, RGB from "
                    "the PNG and, as heldout_generated_mp4, from the mp4), and the same 8 scenes with randomised "
                    "appearance, cloth-heldout3403-rand (heldout_generated_randomized, "
                    "heldout_generated_randomized_mp4); the test seeds (2026, 7070) are never used",
    },
}


def training_videos(files, videos_root, prefix="", folder="pulley_group"):
    """[{video, outputs_sha256}] of the cache files (train-rand/5.npz -> train-rand/pulley_group/5)."""
    out = []
    for f in files:
        root, name = os.path.split(f)
        # A zoom-X cache holds full-resolution windows of the train-X videos (prep_data --zoom).
        if root.startswith("zoom-"):
            root = "train-" + root[len("zoom-"):]
        video = os.path.join(root, folder, os.path.splitext(name)[0])
        data = open(os.path.join(videos_root, video, "outputs.json"), "rb").read()
        out.append({"video": prefix + video, "outputs_sha256": hashlib.sha256(data).hexdigest()})
    return out


def all_training_videos(ck, videos_root, init_roots, folder="pulley_group"):
    """The training videos of a checkpoint and of every checkpoint it was initialised from,
    each once."""
    out, seen = [], set()
    level, roots = ck, [videos_root] + list(init_roots)
    for root in roots:
        if level is None:
            break
        prefix = "" if os.path.normpath(root) == os.path.normpath(videos_root) else "pretraining/"
        for video in training_videos(level["training_files"], root, prefix, folder):
            key = (video["video"], video["outputs_sha256"])
            if key not in seen:
                seen.add(key)
                out.append(video)
        level = level.get("init")
    if level is not None:
        raise SystemExit("an earlier stage has no --init-videos directory")
    return out


def stages(ck):
    """Training stages, first first: iterations, minutes and starting point."""
    chain, level = [], ck
    while level is not None:
        chain.append(level)
        level = level.get("init")
    out = []
    for index, level in enumerate(reversed(chain)):
        args = level.get("args", {})
        out.append({
            "stage": index + 1,
            "iterations": level.get("iter", level.get("iterations")),
            "minutes": round(level["seconds"] / 60, 1) if "seconds" in level else level.get("minutes"),
            "from": "scratch" if index == 0 else "the previous stage",
            "scale_augmentation": args.get("scale", [0.8, 1.25]) if args else None,
            "caches": [os.path.basename(c) for c in args.get("cache", [])] if args else None,
        })
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ckpt_json")
    ap.add_argument("eval_json")
    ap.add_argument("model")
    ap.add_argument("out")
    ap.add_argument("--score-thresh", type=float, default=0.3)
    ap.add_argument("--nms", type=float, default=0.5)
    ap.add_argument("--detections", type=int, default=24)
    ap.add_argument("--videos", required=True, help="directory holding the generated data roots")
    ap.add_argument("--init-videos", action="append", default=[],
                    help="per earlier stage (train.py --init, most recent first), the directory holding its data "
                         "roots; a stage whose directory is --videos is listed as is, another under pretraining/")
    ap.add_argument("--init-generate", action="append", default=[],
                    help="the generate commands of the pretraining data (repeatable)")
    ap.add_argument("--loss-csv", help="train.py's loss.csv: final losses = mean of its last 10 rows")
    ap.add_argument("--scenario", default="rope", choices=["rope", "fluid", "ball", "cloth"])
    ap.add_argument("--eval-randomized", help="evaluate.py's JSON of the held-out scenes with randomised appearance")
    a = ap.parse_args()
    sc = scenario(a.scenario)
    classes, text = sc["classes"], TEXT[a.scenario]
    ck = json.load(open(a.ckpt_json))
    ev = json.load(open(a.eval_json))
    if a.eval_randomized:
        rand = json.load(open(a.eval_randomized))
        for name in ("heldout_generated", "heldout_generated_mp4"):
            if name in rand:
                ev[name.replace("heldout_generated", "heldout_generated_randomized")] = rand[name]
    args = ck["args"]
    final = ck["last_losses"]
    if a.loss_csv:
        import csv
        rows = list(csv.DictReader(open(a.loss_csv)))[-10:]
        keys = ["loss", "loss_classifier", "loss_box_reg", "loss_mask", "loss_objectness", "loss_rpn_box_reg"]
        final = {k: round(sum(float(r[k]) for r in rows) / len(rows), 4) for k in keys}
        final["iterations_averaged"] = f"{rows[0]['iter']}..{rows[-1]['iter']} (10-iteration means)"
    meta = {
        "model": os.path.basename(a.model),
        "sha256": hashlib.sha256(open(a.model, "rb").read()).hexdigest(),
        "bytes": os.path.getsize(a.model),
        "classes": {str(k): v for k, v in classes.items()},
        "class_note": "labels are 1-based, 0 = background (never output); colour is not a class",
        "input": {
            "name": "images_tensors", "shape": [3, "H", "W"], "dtype": "float32",
            "format": "RGB, values in [0,1] (uint8 / 255), CHW, no batch dimension",
            "size": [IN_W, IN_H], "size_note": "trained at 480x270 (width x height); frames are area-downscaled to it. "
            "H, W are dynamic but other sizes were never trained. Normalization (ImageNet mean/std) and "
            "zero-padding to a multiple of 32 happen inside the graph; there is no resize in the graph.",
        },
        "outputs": {
            "boxes": "float32 [N,4] x1,y1,x2,y2 in input pixels (continuous coordinates: a box covering pixel "
                     "columns 10..19 is x1=10, x2=20; training targets were [min_x, min_y, max_x+1, max_y+1])",
            "labels": f"int64 [N] class ids 1..{len(classes)}",
            "scores": "float32 [N] descending",
            "masks": "float32 [N,1,28,28] raw sigmoid probabilities of the detection's own class over its box "
                     "(not pasted); paste like torchvision paste_masks_in_image(padding=1) and threshold at 0.5",
        },
        "baked_in": {"score_thresh": a.score_thresh, "nms_iou": a.nms, "nms": "per class",
                     "detections_per_img": a.detections, "rpn_pre_nms_top_n": 500, "rpn_post_nms_top_n": 200},
        "architecture": ck["config"],
        "export": "torch.onnx.export legacy (dynamo=False), opset 17, torch 2.15.0, torchvision 0.29.2",
        "training": {
            "seed": args["seed"], "seeds_note": "torch.manual_seed, numpy.random.seed, random.seed and the sampler's "
            "random.Random all use this seed (training is not bit-reproducible: data arrived while training)",
            "iterations": ck["iter"], "minutes": round(ck["seconds"] / 60, 1), "batch": args["batch"],
            "optimizer": f"AdamW lr {args['lr']} wd 1e-4, {args['warmup']}-iteration linear warm-up, cosine decay "
                         "over the wall-clock budget to 5%, grad-norm clip 10",
            "torch_threads": args["threads"], "final_losses": final,
            "seconds_per_iteration": round(ck["seconds"] / max(ck["iter"], 1), 3),
            "augmentation": f"scale x U({args.get('scale', [0.8, 1.25])[0]},{args.get('scale', [0.8, 1.25])[1]}) "
                            "with a random shift (p=0.7), horizontal flip p=0.5, wall texture (two octaves of "
                            f"value noise on the background, cell 1-12 px, contrast U(0.05,0.45), p={args.get('texture', 0.0)}), "
                            "brightness x U(0.75,1.25), contrast x U(0.8,1.2), saturation x U(0.85,1.15); hue "
                            "never changed. The generator randomises light, wall, colours (within their names), "
                            f"{text['randomised']} (--appearance randomized)",
        },
        "data": {
            "generated": {
                "commands": text["generate"],
                "train_videos": ck["generated_videos"], "train_frames": ck["generated_frames"],
                "mix": text["mix"],
                "frames_note": text["frames_note"],
                "frame_key": "frame_NNNNN.png is annotation key NNNNN+1 (checked: boxes equal mask boxes)",
            },
            "training_videos": all_training_videos(ck, a.videos, a.init_videos, sc["folder"]),
            "held_out": text["held_out"],
        },
        "stages": stages(ck),
        "pretraining_commands": a.init_generate,
        "metrics": ev,
        "metrics_note": "AP@0.5 (all-point interpolated), per class, onnxruntime with the baked-in score threshold "
                        "(recall is capped by it); masks pasted with paste_masks_in_image(padding=1) > 0.5 and "
                        "compared at 480x270; null = no ground truth of that class in the set",
    }
    json.dump(meta, open(a.out, "w"), indent=1)


if __name__ == "__main__":
    main()
