"""Perception work per question family of a saved run: frames decoded and run through the
detector, API time, and frames per second of API time.

  python3 scripts/run_work.py RUN_DIR [RUN_DIR ...]

Reads RUN_DIR/predictions.jsonl (the last record of each unit). A video's first-pass frames are
decoded once per worker and memoised, so the unit that first needs them carries their cost; the
per-question figures are means over every question of the family.
"""
import collections
import json
import sys


def main(runs):
    for run in runs:
        units = {}
        for line in open(f"{run}/predictions.jsonl"):
            record = json.loads(line)
            units[record["unit"]] = record
        families = collections.OrderedDict()
        for record in units.values():
            row = families.setdefault(record["family"], {"questions": set(), "decoded": 0, "detected": 0, "api_ms": 0})
            row["questions"].add(record["question_id"])
            work = record.get("work") or {}
            row["decoded"] += work.get("frames_decoded", 0)
            row["detected"] += work.get("detections", 0)
            row["api_ms"] += record.get("api_ms", 0)
        print(f"## {run}")
        print("| family | questions | frames decoded / question | detector frames / question | API s | frames/s |")
        print("|---|---:|---:|---:|---:|---:|")
        total = {"q": 0, "decoded": 0, "ms": 0}
        for family, row in sorted(families.items()):
            q = len(row["questions"])
            fps = row["decoded"] / (row["api_ms"] / 1000) if row["api_ms"] else 0.0
            print(f"| {family} | {q} | {row['decoded'] / q:.1f} | {row['detected'] / q:.1f} | {row['api_ms'] / 1000:.1f} | {fps:.1f} |")
            total["q"] += q
            total["decoded"] += row["decoded"]
            total["ms"] += row["api_ms"]
        fps = total["decoded"] / (total["ms"] / 1000) if total["ms"] else 0.0
        print(f"| all | {total['q']} | {total['decoded'] / max(total['q'], 1):.1f} | | {total['ms'] / 1000:.1f} | {fps:.1f} |")
        print()


if __name__ == "__main__":
    main(sys.argv[1:])
