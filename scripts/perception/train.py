"""Train the contphy-eval Mask R-CNN on 480x270 caches (prep_data.py) with a wall-clock budget.

  python train.py --cache CACHE_DIR [--cache CACHE_DIR ...] --out CKPT_DIR --minutes 55
Generated videos only: the real video is a held-out test and never an input here. The cache
directories are re-scanned every 100 iterations (generation may still be running); the
checkpoint's metadata lists every cache file trained on.
Augmentation (the camera and the sensor, beyond what the generator randomises): horizontal flip,
scale x U(0.8, 1.25) with a random shift (the release camera re-frames each scene), brightness,
contrast and saturation. Hue is never changed: colour names are labels.
--scenario fluid trains the fluid model (classes common.FLUID_CLASSES) on fluid caches, --scenario
ball the ball model (common.BALL_CLASSES) on ball caches, --scenario cloth the cloth model
(common.CLOTH_CLASSES) on cloth caches.
"""
import argparse
import csv
import glob
import json
import math
import os
import random
import time

import numpy as np
import torch

from common import scenario, targets_from_map
from model import model_config, build_model


class Pool:
    def __init__(self, caches):
        self.caches = caches
        self.loaded = []
        self.gen = []  # (imgs, inst, classes, index)
        self.rescan()

    def rescan(self):
        for cache in self.caches:
            for p in sorted(glob.glob(os.path.join(cache, "*.npz"))):
                if p in self.loaded:
                    continue
                try:
                    d = np.load(p)
                    imgs, inst, cls = d["imgs"], d["inst"], d["classes"]
                except Exception:
                    continue
                self.loaded.append(p)
                for i in range(len(imgs)):
                    self.gen.append((imgs, inst, cls, i))

    def sample(self, rng):
        return self.gen[rng.randrange(len(self.gen))]


def rescale(img, m, rng, scale):
    """Scale by U(*scale) about a random point and crop/pad back to the input size (padding
    with the image's median colour, the wall)."""
    h, w = m.shape
    s = rng.uniform(*scale)
    nh, nw = max(1, round(h * s)), max(1, round(w * s))
    ys = np.clip(((np.arange(nh) + 0.5) / s - 0.5).round().astype(int), 0, h - 1)
    xs = np.clip(((np.arange(nw) + 0.5) / s - 0.5).round().astype(int), 0, w - 1)
    # Bilinear for the image, nearest for the instance map.
    t = torch.from_numpy(np.ascontiguousarray(img.transpose(2, 0, 1)))[None]
    big = torch.nn.functional.interpolate(t, size=(nh, nw), mode="bilinear", align_corners=False)[0]
    big = big.numpy().transpose(1, 2, 0)
    bm = m[ys][:, xs]
    out = np.empty_like(img)
    out[:] = np.median(img.reshape(-1, 3), axis=0)
    om = np.zeros_like(m)
    oy = rng.randint(min(0, h - nh), max(0, h - nh))
    ox = rng.randint(min(0, w - nw), max(0, w - nw))
    sy0, dy0 = max(0, -oy), max(0, oy)
    sx0, dx0 = max(0, -ox), max(0, ox)
    ch, cw = min(nh - sy0, h - dy0), min(nw - sx0, w - dx0)
    out[dy0:dy0 + ch, dx0:dx0 + cw] = big[sy0:sy0 + ch, sx0:sx0 + cw]
    om[dy0:dy0 + ch, dx0:dx0 + cw] = bm[sy0:sy0 + ch, sx0:sx0 + cw]
    return out, om


def wall_texture(img, m, rng):
    """Multiplies the wall (instance 0) by a random procedural texture, so that a textured
    background is not taken for rope: two octaves of bilinear value noise with a cell of 1 to 12
    pixels, stretched up to 4x either way, contrast U(0.05, 0.45). Objects keep their pixels;
    the wall keeps its light and shadows under the texture."""
    h, w = m.shape
    noise_rng = np.random.default_rng(rng.randrange(2 ** 31))
    factor = np.zeros((h, w), np.float32)
    cell = rng.choice([1, 1, 2, 2, 3, 4, 6, 8, 12])
    stretch = rng.choice([1, 1, 1, 2, 4])
    cells = (cell * stretch, cell) if rng.random() < 0.5 else (cell, cell * stretch)
    for octave, weight in ((1, 0.65), (3, 0.35)):
        cy, cx = cells[0] * octave, cells[1] * octave
        gh, gw = h // cy + 2, w // cx + 2
        grid = torch.from_numpy(noise_rng.random((gh, gw), dtype=np.float32))[None, None]
        up = torch.nn.functional.interpolate(grid, size=(gh * cy, gw * cx), mode="bilinear",
                                             align_corners=False)[0, 0, :h, :w].numpy()
        factor += weight * (up - 0.5) * 2.0
    factor = 1.0 + rng.uniform(0.05, 0.45) * factor
    img = np.array(img, copy=True)
    bg = m == 0
    img[bg] = np.clip(img[bg] * factor[bg, None], 0.0, 1.0)
    return img


def make_sample(item, rng, scale=(0.8, 1.25), texture=0.0):
    """One augmented training sample: rescale by U(*scale) (p 0.7), flip, wall texture (p texture),
    brightness, contrast and saturation."""
    imgs, inst, cls, i = item
    img = imgs[i].astype(np.float32) / 255.0
    m = inst[i]
    if rng.random() < 0.7:
        img, m = rescale(img, m, rng, scale)
    if rng.random() < 0.5:  # horizontal flip
        img = img[:, ::-1]
        m = m[:, ::-1]
    if rng.random() < texture:
        img = wall_texture(img, m, rng)
    classes = {iid: int(cls[iid]) for iid in np.unique(m) if iid != 0}
    boxes, labels, masks = targets_from_map(m, classes)
    # Brightness, contrast and saturation; hue is left alone (colour names are labels).
    img = img * rng.uniform(0.75, 1.25)
    mean = img.mean()
    img = mean + (img - mean) * rng.uniform(0.8, 1.2)
    grey = img.mean(axis=2, keepdims=True)
    img = np.clip(grey + (img - grey) * rng.uniform(0.85, 1.15), 0.0, 1.0).astype(np.float32)
    t = {"boxes": torch.from_numpy(np.ascontiguousarray(boxes)), "labels": torch.from_numpy(labels),
         "masks": torch.from_numpy(np.ascontiguousarray(masks))}
    return torch.from_numpy(np.ascontiguousarray(img.transpose(2, 0, 1))), t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cache", required=True, action="append")
    ap.add_argument("--scenario", default="rope", choices=["rope", "fluid", "ball", "cloth"],
                    help="the class table (and so the number of classes) of the model")
    ap.add_argument("--out", required=True)
    ap.add_argument("--minutes", type=float, default=50)
    ap.add_argument("--batch", type=int, default=2)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--warmup", type=int, default=100)
    ap.add_argument("--seed", type=int, default=20261123)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--ckpt-minutes", type=float, default=10)
    ap.add_argument("--log-every", type=int, default=10)
    ap.add_argument("--scale", type=float, nargs=2, default=[0.8, 1.25], metavar=("LOW", "HIGH"),
                    help="range of the random rescale augmentation")
    ap.add_argument("--texture", type=float, default=0.0,
                    help="probability of the wall-texture augmentation (wall_texture)")
    ap.add_argument("--init", help="start from this checkpoint (.pt) instead of from scratch; its own "
                    "training files are carried into this run's metadata")
    a = ap.parse_args()

    torch.set_num_threads(a.threads)
    random.seed(a.seed)
    np.random.seed(a.seed)
    torch.manual_seed(a.seed)
    rng = random.Random(a.seed)
    os.makedirs(a.out, exist_ok=True)

    pool = Pool(a.cache)
    while not pool.gen:  # the first videos may still be on their way
        time.sleep(20)
        pool.rescan()
    print(f"generated frames {len(pool.gen)} from {len(pool.loaded)} videos", flush=True)
    num_classes = scenario(a.scenario)["num_classes"]
    config = model_config(num_classes)
    model = build_model(num_classes=num_classes)
    init_meta = None
    if a.init:
        state = torch.load(a.init, map_location="cpu", weights_only=False)
        model.load_state_dict(state["model"])
        init_meta = {"checkpoint": os.path.basename(a.init), "iterations": state["meta"]["iter"],
                     "minutes": round(state["meta"]["seconds"] / 60, 1),
                     "training_files": state["meta"]["training_files"], "args": state["meta"].get("args"),
                     "init": state["meta"].get("init")}
        print(f"initialised from {a.init} ({init_meta['iterations']} iterations)", flush=True)
    model.train()
    params = [p for p in model.parameters() if p.requires_grad]
    opt = torch.optim.AdamW(params, lr=a.lr, weight_decay=1e-4)
    budget = a.minutes * 60
    start = time.time()
    last_ckpt = start
    log = open(os.path.join(a.out, "loss.csv"), "w", newline="")
    wr = csv.writer(log)
    wr.writerow(["iter", "seconds", "lr", "loss", "loss_classifier", "loss_box_reg", "loss_mask",
                 "loss_objectness", "loss_rpn_box_reg", "generated_frames"])
    acc, n_acc = {}, 0
    it = 0

    def save(tag):
        meta = {"iter": it, "seconds": time.time() - start, "args": vars(a), "config": config,
                "generated_frames": len(pool.gen), "generated_videos": len(pool.loaded),
                "training_files": [os.path.relpath(p, os.path.dirname(c)) for p in pool.loaded
                                   for c in a.cache if os.path.dirname(p) == os.path.normpath(c)], "last_losses": {k: v / max(n_acc, 1) for k, v in acc.items()},
                "init": init_meta}
        torch.save({"model": model.state_dict(), "meta": meta}, os.path.join(a.out, f"{tag}.pt"))
        json.dump(meta, open(os.path.join(a.out, f"{tag}.json"), "w"), indent=1)

    while True:
        el = time.time() - start
        if el > budget:
            break
        frac = el / budget
        lr = a.lr * min(1.0, (it + 1) / a.warmup) * (0.05 + 0.95 * 0.5 * (1 + math.cos(math.pi * frac)))
        for g in opt.param_groups:
            g["lr"] = lr
        if it % 100 == 0 and it:
            pool.rescan()
        batch = [make_sample(pool.sample(rng), rng, tuple(a.scale), a.texture) for _ in range(a.batch)]
        losses = model([b[0] for b in batch], [b[1] for b in batch])
        loss = sum(losses.values())
        if not torch.isfinite(loss):
            print("non-finite loss, skipping", {k: v.item() for k, v in losses.items()}, flush=True)
            opt.zero_grad()
            it += 1
            continue
        opt.zero_grad()
        loss.backward()
        torch.nn.utils.clip_grad_norm_(params, 10.0)
        opt.step()
        it += 1
        for k, v in losses.items():
            acc[k] = acc.get(k, 0.0) + v.item()
        acc["loss"] = acc.get("loss", 0.0) + loss.item()
        n_acc += 1
        if it % a.log_every == 0:
            wr.writerow([it, round(time.time() - start, 1), f"{lr:.6g}"] +
                        [round(acc[k] / n_acc, 4) for k in ["loss", "loss_classifier", "loss_box_reg", "loss_mask",
                                                            "loss_objectness", "loss_rpn_box_reg"]] + [len(pool.gen)])
            log.flush()
            print(it, round(time.time() - start), f"{lr:.2e}", {k: round(v / n_acc, 3) for k, v in acc.items()},
                  len(pool.gen), flush=True)
            last = (acc, n_acc)
            acc, n_acc = {}, 0
        if time.time() - last_ckpt > a.ckpt_minutes * 60:
            save("latest")
            save(f"it{it:05d}")
            last_ckpt = time.time()
    if n_acc == 0 and it >= a.log_every:
        acc, n_acc = last
    save("final")
    save("latest")
    print("done", it, "iterations", round(time.time() - start), "s", flush=True)


if __name__ == "__main__":
    main()
