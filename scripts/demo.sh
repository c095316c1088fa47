#!/usr/bin/env bash
# The README's first command: installs ONNX Runtime into the project (scripts/setup-onnxruntime.sh),
# builds, and evaluates every question of the embedded real rope video with ContPRO's pipeline
# (--perception maskrcnn --dynamics simulate). Without a runtime (no pip, not Linux x86_64) it
# says so and runs the oracle perception instead. Extra arguments go to contphy-eval.
set -euo pipefail
cd "$(dirname "$0")/.."

perception=(--perception maskrcnn --dynamics simulate)
if ! scripts/setup-onnxruntime.sh; then
  echo "demo: ONNX Runtime could not be installed; running with --perception annotation" >&2
  perception=(--perception annotation --dynamics simulate)
fi
exec cargo run --release --locked -- --data eval/demo --questions eval/demo/pulley_group/0.json \
  --out runs/demo "${perception[@]}" "$@"
