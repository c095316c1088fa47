#!/usr/bin/env bash
# The README's first command: installs what the demo needs (Debian's ffmpeg, to decode the video,
# through apt-get when it can; ONNX Runtime into the project, scripts/setup-onnxruntime.sh),
# builds, and evaluates every question of the embedded real rope video with ContPRO's pipeline
# (--perception maskrcnn --dynamics simulate), then every question of the two embedded generated
# fluid videos, of the two generated cloth videos and of the two generated ball videos with the
# oracle backends. Without a runtime (no pip, not Linux x86_64) it
# says so and runs the oracle perception instead. Extra arguments go to contphy-eval.
set -euo pipefail
cd "$(dirname "$0")/.."

# ffmpeg decodes the demo's mp4s. Install it as .ci/run does when apt-get can run (as root or
# with password-less sudo); otherwise stop before building, with the one command to type.
if [ -z "${CONTPHY_FFMPEG_DIR:-}" ] && ! command -v ffmpeg >/dev/null 2>&1; then
  sudo=""
  if [ "$(id -u)" != 0 ]; then
    if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
      sudo="sudo -n"
    else
      sudo="unavailable"
    fi
  fi
  if [ "${sudo}" != unavailable ] && command -v apt-get >/dev/null 2>&1; then
    echo "demo: installing ffmpeg (apt-get) to decode the demo video ..." >&2
    if ! { ${sudo} apt-get update -qq >/dev/null &&
      DEBIAN_FRONTEND=noninteractive ${sudo} apt-get install -y -qq --no-install-recommends ffmpeg >/dev/null; }; then
      echo "demo: apt-get could not install ffmpeg" >&2
    fi
  fi
  if ! command -v ffmpeg >/dev/null 2>&1; then
    echo "demo: ffmpeg is needed to decode the demo video; install it (Debian/Ubuntu: sudo apt-get install ffmpeg) and run scripts/demo.sh again" >&2
    exit 1
  fi
fi

perception=(--perception maskrcnn --dynamics simulate)
if ! scripts/setup-onnxruntime.sh; then
  echo "demo: ONNX Runtime could not be installed; running with --perception annotation" >&2
  perception=(--perception annotation --dynamics simulate)
fi
# A new run directory each time (runs/demo, runs/demo-2, ...): earlier runs are kept.
out=runs/demo
n=1
while [ -e "${out}/manifest.json" ] || [ -e "${out}-fluid/manifest.json" ] ||
  [ -e "${out}-cloth/manifest.json" ] || [ -e "${out}-ball/manifest.json" ]; do
  n=$((n + 1))
  out="runs/demo-${n}"
done
cargo run --release --locked -- --data eval/demo --questions eval/demo/pulley_group/0.json \
  --out "${out}" "${perception[@]}" "$@"
# Fluid: two generated videos (eval/demo/fluid_slides/), every question the engine made for them,
# with the oracle backends (ContPRO's fluid pipeline, --dynamics simulate and --perception maskrcnn,
# is measured in docs/data/fluid.md; these 320x180 videos are smaller than its detector's input).
cargo run --release --locked -- --data eval/demo --questions eval/demo/fluid_slides/0.json \
  --questions eval/demo/fluid_slides/1.json --out "${out}-fluid" \
  --perception annotation --dynamics annotation "$@"
# Cloth: two generated videos (eval/demo/cloth_collision/), every question the engine made for
# them, with the oracle backends (cloth videos are answered from their annotations in this version).
cargo run --release --locked -- --data eval/demo --questions eval/demo/cloth_collision/0.json \
  --questions eval/demo/cloth_collision/1.json --out "${out}-cloth" \
  --perception annotation --dynamics annotation "$@"
# Ball: two generated videos (eval/demo/soft_body/), every question the engine made for them, with
# the oracle backends (ball videos are answered from their annotations in this version).
exec cargo run --release --locked -- --data eval/demo --questions eval/demo/soft_body/0.json \
  --questions eval/demo/soft_body/1.json --out "${out}-ball" \
  --perception annotation --dynamics annotation "$@"
