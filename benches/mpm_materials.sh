#!/usr/bin/env bash
# The MPM core's step rate per material next to Taichi 1.7.4's, on the mpm88 configuration at
# 8,192 particles: the example's liquid and the elastoplastic solids of `bench mpm88 --material`
# (elastic, plastic) on the same grid, dt, gravity and initial positions, for ours (f64) and
# Taichi (f32, f64) at 1 and 2 threads. Prints each JSON result, then a summary table of million
# particle substeps per second (best of REPEATS) and the f64 parity of each material after the
# run: relative difference of mean position, kinetic energy and mean J between ours and Taichi
# f64 at one thread, and how many particle substeps each side's return map projected.
#
# Usage: benches/mpm_materials.sh [STEPS [REPEATS]]   (defaults 2000 and 2)
# Environment: TAICHI_VENV, a virtualenv that already has taichi 1.7.4 and numpy, replaces
# target/venv-taichi (the default, created on first use).
set -euo pipefail
cd "$(dirname "$0")/.."
steps="${1:-2000}"
repeats="${2:-2}"
venv="${TAICHI_VENV:-target/venv-taichi}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet "taichi==1.7.4" numpy
fi
cargo build --release --locked --quiet
"$venv/bin/python" benches/make_mpm88_init.py --out target/mpm88 --n 8192 >/dev/null
init=target/mpm88/mpm88_init_8192.npy
results=target/mpm88/materials.jsonl
: >"$results"
for repeat in $(seq "$repeats"); do
    for material in liquid elastic plastic; do
        for threads in 1 2; do
            target/release/contphy-eval bench mpm88 --init "$init" --steps "$steps" \
                --threads "$threads" --material "$material" | "$venv/bin/python" -c \
                'import json,sys; print(json.dumps(json.load(sys.stdin)))' | tee -a "$results"
            for precision in f32 f64; do
                flag=""
                [ "$precision" = f64 ] && flag="--f64"
                "$venv/bin/python" benches/mpm88_taichi.py --init "$init" --steps "$steps" \
                    --threads "$threads" --material "$material" $flag | tee -a "$results"
            done
        done
    done
done
"$venv/bin/python" - "$results" <<'PY'
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
for row in rows:  # the liquid's reports predate --material and do not name it
    row.setdefault("material", "liquid")

def runs(impl, precision, material, threads):
    return [row for row in rows
            if (row["implementation"], row["precision"], row["material"], row["threads"])
            == (impl, precision, material, threads)]

def best(impl, precision, material, threads):
    return max(row["particle_steps_per_s"] for row in runs(impl, precision, material, threads))

materials = ("liquid", "elastic", "plastic")
print(f"\nmpm88 configuration, 8,192 particles, {rows[0]['steps']} substeps, best of "
      f"{max(len(runs('contphy-eval', 'f64', 'liquid', 1)), 1)}; "
      "million particle substeps per second\n")
print("| material | threads | ours (f64) | Taichi f32 | Taichi f64 | ours / Taichi f32 |")
print("|---|---:|---:|---:|---:|---:|")
for material in materials:
    for threads in (1, 2):
        ours = best("contphy-eval", "f64", material, threads)
        t32 = best("taichi", "f32", material, threads)
        t64 = best("taichi", "f64", material, threads)
        print(f"| {material} | {threads} | {ours / 1e6:.2f} | {t32 / 1e6:.2f} | "
              f"{t64 / 1e6:.2f} | {ours / t32:.2f} |")
print("\nParity after the run, ours f64 against Taichi f64 (relative difference; "
      "Taichi f32 in brackets)\n")
print("| material | threads | mean x | mean y | kinetic energy | mean J | yielded (ours / Taichi f64) |")
print("|---|---:|---:|---:|---:|---:|---:|")
for material in materials:
    for threads in (1, 2):
        ours = runs("contphy-eval", "f64", material, threads)[0]
        t64 = runs("taichi", "f64", material, threads)[0]
        t32 = runs("taichi", "f32", material, threads)[0]
        if material != "liquid":
            for key in ("youngs_modulus", "poisson_ratio", "yield_stress"):
                assert ours[key] == t64[key], f"{material}: {key} {ours[key]} != {t64[key]}"
        cells = []
        for key in ("mean_x", "mean_y", "kinetic_energy", "mean_J"):
            d64 = abs(ours[key] - t64[key]) / abs(t64[key])
            d32 = abs(ours[key] - t32[key]) / abs(t32[key])
            cells.append(f"{d64:.1e} [{d32:.1e}]")
        yielded = (f"{ours['yielded']:,} / {t64['yielded']:,}" if material != "liquid"
                   else "-")
        print(f"| {material} | {threads} | " + " | ".join(cells) + f" | {yielded} |")
PY
