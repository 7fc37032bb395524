#!/usr/bin/env bash
# The stability matrix of docs/stability.md: each point is a shipped case run with a few keys
# overridden to an extreme (impact speed, step factor, h/Δp, particles through a thickness,
# tension, a soft/stiff contact pair, the surface contact, a long run). For each it prints one CSV
# row: whether the run finished, its steps, final and largest energy balance error (the largest
# ignoring the first 5% of the run, where the energies are too small for a relative error to
# mean much), and the error message of a run that stopped.
#   scripts/stability-matrix.sh [OUT_DIR=out/stability] [SPHFEM=build/app/sphfem]
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/stability}
sphfem=${2:-build/app/sphfem}
mkdir -p "$out"

# The bars moved together: bar A's last particle (cell-centred, 5 mm inside its box) 21 mm from
# bar B's face, just beyond the contact's reach 2h = 20 mm, so that slow bars also meet.
close_bars=(--set 'bodies.bar_a.geometry.box={min: [0, 0, -0.2], max: [0.05, 0.05, 0]}'
  --set 'bodies.bar_b.geometry.box={min: [0, 0, 0.016], max: [0.05, 0.05, 0.216]}')
speed() { echo --set "bodies.bar_a.velocity=[0,0,$1]" --set "bodies.bar_b.velocity=[0,0,-$1]"; }
# The surface contact (docs/contact.md) in place of the case's kernel contact, its penalty the
# default or the given one (into the array `surface`, since the value holds spaces); and the bars
# 1 mm apart, since it acts only where they touch.
surface_contact() { surface=(--set "contact.0={bodies: [bar_a, bar_b], model: surface${1:+, penalty: $1}}"); }
touching=(--set 'bodies.bar_a.geometry.box={min: [0, 0, -0.2], max: [0.05, 0.05, 0]}'
  --set 'bodies.bar_b.geometry.box={min: [0, 0, 0.001], max: [0.05, 0.05, 0.201]}')
soft='{model: elastic, density: 1000, youngs_modulus: 1.0e9, poisson_ratio: 0.3}'

echo "point,case,finished,steps,final_balance_error,largest_balance_error,message"
run() { # name case overrides...
  local name=$1 case=$2
  shift 2
  local dir="$out/$name"
  rm -rf "$dir"
  local file="cases/$case/case.yaml"
  [[ $case == */* ]] && file="cases/$case.yaml" # a case folder's other file, e.g. bar_impact/reference_fe
  "$sphfem" run "$file" -o "$dir" -q "$@" >"$out/$name.log" 2>&1
  local rc=$?
  python3 - "$name" "$case" "$rc" "$dir" "$out/$name.log" <<'EOF'
import csv, json, os, sys
name, case, rc, d, log = sys.argv[1:]
steps = final = largest = ""
if os.path.exists(f"{d}/summary.json"):
    s = json.load(open(f"{d}/summary.json"))
    steps, final = s["steps"], f'{s["energy"]["balance_error"]:.3g}'
if os.path.exists(f"{d}/history.csv"):
    rows = list(csv.DictReader(open(f"{d}/history.csv")))
    e0, t_end = float(rows[0]["energy.total"]), float(rows[-1]["time"])
    worst = 0.0
    for r in rows:
        if float(r["time"]) < 0.05 * t_end:
            continue
        k, i = float(r["energy.kinetic"]), float(r["energy.internal"])
        w, t = float(r["energy.external_work"]), float(r["energy.total"])
        scale = max(k + i, abs(w), e0)
        if scale > 0:
            worst = max(worst, abs(t - w - e0) / scale)
    largest = f"{worst:.3g}"
message = ""
if rc != "0":
    lines = [l.strip() for l in open(log) if "error" in l]
    message = lines[-1].replace(",", ";") if lines else f"exit {rc}"
print(",".join(map(str, [name, case, "yes" if rc == "0" else "no", steps, final, largest, message])))
EOF
}

run speed_1 bar_impact "${close_bars[@]}" $(speed 1) --set time.end=3.0e-3
run speed_200 bar_impact
run speed_3000 bar_impact $(speed 3000) --set time.end=5.0e-5
for cfl in 0.05 0.3 0.6 0.9 1.0; do
  run cfl_$cfl bar_impact --set time.cfl=$cfl --set sph.cfl=$cfl
  run sph_cfl_$cfl bar_pressed_sph --set sph.cfl=$cfl
done
for hf in 1.0 1.2 1.5 2.0; do
  run h_$hf bar_pressed_sph --set bodies.bar.h_factor=$hf
done
run compression_4GPa bar_pressed_sph --set loads.0.pressure=4.0e9
run tension_4GPa bar_pressed_sph --set loads.0.pressure=-4.0e9
run tension_40GPa bar_pressed_sph --set loads.0.pressure=-40.0e9
run thickness_2 bar_pressed_sph --set bodies.bar.spacing=0.0025 # 2 particles across 5 mm
run thickness_1 bar_pressed_sph --set bodies.bar.spacing=0.005  # 1 particle across 5 mm
run soft_fe_bar bar_impact --set "materials.soft=$soft" --set bodies.bar_b.material=soft
run soft_sph_bar bar_impact --set "materials.soft=$soft" --set bodies.bar_a.material=soft
run long_10x bar_impact --set time.end=2.0e-3
surface_contact
run surface_1 bar_impact "${surface[@]}" "${touching[@]}" $(speed 1) --set time.end=7.0e-4
run surface_200 bar_impact "${surface[@]}"
run surface_3000 bar_impact "${surface[@]}" $(speed 3000) --set time.end=5.0e-5
run surface_fe_3000 bar_impact/reference_fe "${surface[@]}" $(speed 3000) --set time.end=5.0e-5
surface_contact 2.7865e12 # 10 × the default
run surface_3000_stiff bar_impact "${surface[@]}" $(speed 3000) --set time.end=5.0e-5
surface_contact 2.7865e13 # 100 × the default
run surface_penalty_100x bar_impact "${surface[@]}"
# 1 m/s onto the plate: its face 0.01 mm beyond the core's spheres (Δp/2 = 0.75 mm above the
# plate), so that it presses on the plate for 90 µs.
run plate_1ms borvik_12mm --set preset=coarse --set projectile.velocity=1 --set projectile.gap=0.00076 \
  --set time.end=1.0e-4
run plate_2mm_core borvik_12mm --set preset=coarse --set core.spacing=0.006 --set time.end=1.0e-4
for v in 20 1000 3000; do
  run plate_${v}ms borvik_12mm --set preset=coarse --set projectile.velocity=$v --set time.end=1.0e-4
done
run plate_cfl_1.0 borvik_12mm --set preset=coarse --set time.cfl=1.0 --set sph.cfl=1.0 --set time.end=1.0e-4
