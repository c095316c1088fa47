#!/usr/bin/env bash
# Side-by-side MPM benchmark: contphy-eval's MPM core against Taichi 1.7.4 on the exact mpm88
# configuration, in one run. Installs taichi and numpy from PyPI into target/venv-taichi (once),
# writes the initial positions (numpy, seed 0) to target/mpm88/, then runs both at 1 and 2
# threads for 8,192 and 32,768 particles and prints each JSON result and a summary: the speed
# ratio (ours f64 / Taichi f32 and f64, particle substeps per second) and the f64 parity after
# 2,000 substeps (relative difference of mean position, kinetic energy and mean J).
#
# Usage: benches/mpm88.sh [STEPS_8192 [STEPS_32768]]   (defaults 2000 and 1000)
# Environment: TAICHI_VENV, a virtualenv that already has taichi 1.7.4 and numpy, replaces
# target/venv-taichi (the default, created on first use).
set -euo pipefail
cd "$(dirname "$0")/.."
steps_small="${1:-2000}"
steps_large="${2:-1000}"
venv="${TAICHI_VENV:-target/venv-taichi}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet "taichi==1.7.4" numpy
fi
cargo build --release --locked --quiet
"$venv/bin/python" benches/make_mpm88_init.py --out target/mpm88 >/dev/null
results=target/mpm88/results.jsonl
: >"$results"
for particles in 8192 32768; do
    steps=$steps_small
    [ "$particles" = 32768 ] && steps=$steps_large
    init="target/mpm88/mpm88_init_${particles}.npy"
    for threads in 1 2; do
        target/release/contphy-eval bench mpm88 --init "$init" --steps "$steps" \
            --threads "$threads" | "$venv/bin/python" -c \
            'import json,sys; print(json.dumps(json.load(sys.stdin)))' | tee -a "$results"
        for precision in f32 f64; do
            flag=""
            [ "$precision" = f64 ] && flag="--f64"
            "$venv/bin/python" benches/mpm88_taichi.py --init "$init" --steps "$steps" \
                --threads "$threads" $flag | tee -a "$results"
        done
    done
done
"$venv/bin/python" - "$results" <<'PY'
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
def find(impl, precision, particles, threads):
    for row in rows:
        if (row["implementation"] == impl and row["precision"] == precision
                and row["particles"] == particles and row["threads"] == threads):
            return row
summary = []
for particles in (8192, 32768):
    for threads in (1, 2):
        ours = find("contphy-eval", "f64", particles, threads)
        t32 = find("taichi", "f32", particles, threads)
        t64 = find("taichi", "f64", particles, threads)
        entry = {
            "particles": particles, "threads": threads,
            "ours_f64_particle_steps_per_s": ours["particle_steps_per_s"],
            "taichi_f32_particle_steps_per_s": t32["particle_steps_per_s"],
            "taichi_f64_particle_steps_per_s": t64["particle_steps_per_s"],
            "ratio_ours_f64_to_taichi_f32": ours["particle_steps_per_s"] / t32["particle_steps_per_s"],
            "ratio_ours_f64_to_taichi_f64": ours["particle_steps_per_s"] / t64["particle_steps_per_s"],
        }
        if ours["steps"] == t64["steps"]:
            entry["parity_f64_max_relative"] = max(
                abs(ours[k] - t64[k]) / abs(t64[k])
                for k in ("mean_x", "mean_y", "kinetic_energy", "mean_J"))
        summary.append(entry)
print(json.dumps({"summary": summary}, indent=2))
PY
