"""Train the contphy-eval Mask R-CNN on 480x270 caches (prep_data.py) with a wall-clock budget.

  python train.py --cache CACHE_DIR --real REAL_NPZ --out CKPT_DIR --minutes 50
Generated videos are re-scanned every 100 iterations (generation may still be running).
Real frames with annotation keys <= --real-max-key (every --real-every-th) are mixed in with
probability --real-prob; keys above it are held out.
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

from common import targets_from_map
from model import CONFIG, build_model


class Pool:
    def __init__(self, cache, real, real_max_key, real_every):
        self.cache = cache
        self.loaded = set()
        self.gen = []  # (imgs, inst, classes, index)
        self.real = []
        d = np.load(real)
        for i, k in enumerate(d["keys"]):
            if k <= real_max_key and (k - 1) % real_every == 0:
                self.real.append((d["imgs"], d["inst"], d["classes"], i))
        self.real_keys = [int(d["keys"][i]) for *_, i in self.real]
        self.rescan()

    def rescan(self):
        for p in sorted(glob.glob(os.path.join(self.cache, "*.npz"))):
            if p in self.loaded:
                continue
            try:
                d = np.load(p)
                imgs, inst, cls = d["imgs"], d["inst"], d["classes"]
            except Exception:
                continue
            self.loaded.add(p)
            for i in range(len(imgs)):
                self.gen.append((imgs, inst, cls, i))

    def sample(self, rng, real_prob):
        src = self.real if (self.real and rng.random() < real_prob) else self.gen
        return src[rng.randrange(len(src))]


def make_sample(item, rng):
    imgs, inst, cls, i = item
    img = imgs[i].astype(np.float32) / 255.0
    m = inst[i]
    classes = {iid: int(cls[iid]) for iid in np.unique(m) if iid != 0}
    boxes, labels, masks = targets_from_map(m, classes)
    if rng.random() < 0.5:  # horizontal flip
        img = img[:, ::-1]
        masks = masks[:, :, ::-1]
        w = img.shape[1]
        boxes = boxes.copy()
        boxes[:, [0, 2]] = w - boxes[:, [2, 0]]
    img = np.clip(img * rng.uniform(0.8, 1.2), 0.0, 1.0)  # brightness only (no hue shift)
    t = {"boxes": torch.from_numpy(np.ascontiguousarray(boxes)), "labels": torch.from_numpy(labels),
         "masks": torch.from_numpy(np.ascontiguousarray(masks))}
    return torch.from_numpy(np.ascontiguousarray(img.transpose(2, 0, 1))), t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cache", required=True)
    ap.add_argument("--real", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--minutes", type=float, default=50)
    ap.add_argument("--batch", type=int, default=2)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--warmup", type=int, default=100)
    ap.add_argument("--real-prob", type=float, default=0.15)
    ap.add_argument("--real-max-key", type=int, default=100)
    ap.add_argument("--real-every", type=int, default=3)
    ap.add_argument("--seed", type=int, default=20261123)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--ckpt-minutes", type=float, default=10)
    ap.add_argument("--log-every", type=int, default=10)
    a = ap.parse_args()

    torch.set_num_threads(a.threads)
    random.seed(a.seed)
    np.random.seed(a.seed)
    torch.manual_seed(a.seed)
    rng = random.Random(a.seed)
    os.makedirs(a.out, exist_ok=True)

    pool = Pool(a.cache, a.real, a.real_max_key, a.real_every)
    print(f"generated frames {len(pool.gen)}, real frames {len(pool.real)} keys {pool.real_keys}", flush=True)
    model = build_model()
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
        meta = {"iter": it, "seconds": time.time() - start, "args": vars(a), "config": CONFIG,
                "generated_frames": len(pool.gen), "generated_videos": len(pool.loaded),
                "real_keys": pool.real_keys, "last_losses": {k: v / max(n_acc, 1) for k, v in acc.items()}}
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
        batch = [make_sample(pool.sample(rng, a.real_prob), rng) for _ in range(a.batch)]
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
