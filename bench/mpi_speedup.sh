#!/usr/bin/env bash
# Speed of a distributed run on this machine (issue 28): each case at 1 rank × 1 thread,
# 2 ranks × 1 thread and 1 rank × 2 threads, in alternating rounds, best wall time of each
# (summary.json's wall_s: the time loop, meshing and start-up excluded). Prints a Markdown table
# with the speed-ups and the halo bytes the ranks sent per entity-step; compares the two ranks'
# history with the single process's, column by column (identical since the sums are exact,
# 2026-12-06; before, the works of supports and symmetry planes differed in their last digits).
#   bench/mpi_speedup.sh [SPHFEM=build/app/sphfem] [ROUNDS=3] [OUT=/tmp/sphfem_mpi_speedup]
#                        [END=4e-5] [CASES="fe_bar sph_bar borvik_coarse borvik_standard"]
# END: the Børvik shots' time.end (3e-4: the whole shot); CASES: which cases to measure.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
rounds=${2:-3}
out=${3:-/tmp/sphfem_mpi_speedup}
end=${4:-4e-5}
only=${5:-fe_bar sph_bar borvik_coarse borvik_standard}
cases=$here/../cases
mkdir -p "$out"
mpirun_=(mpirun --allow-run-as-root --bind-to none -np 2)

wall() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['wall_s'])" "$1/summary.json"; }
best() { sort -g | head -1; }

measure() { # name case-file keys...
  local name=$1 file=$2
  shift 2
  [[ " $only " == *" $name "* ]] || return 0
  local keys=(-q --set output.frames=false --set time.history_interval=1e-6 "$@")
  "$sphfem" mesh "$file" -o "$out/$name-1x1" "${keys[@]}" >/dev/null
  : >"$out/$name.1x1" && : >"$out/$name.2x1" && : >"$out/$name.1x2"
  for ((r = 0; r < rounds; ++r)); do
    "$sphfem" solve "$file" -o "$out/$name-1x1" "${keys[@]}" --threads 1 >/dev/null
    wall "$out/$name-1x1" >>"$out/$name.1x1"
    OMP_NUM_THREADS=1 "${mpirun_[@]}" "$sphfem" run "$file" -o "$out/$name-2x1" "${keys[@]}" \
      --threads 1 >/dev/null
    wall "$out/$name-2x1" >>"$out/$name.2x1"
    "$sphfem" solve "$file" -o "$out/$name-1x2" "${keys[@]}" --threads 2 >/dev/null
    wall "$out/$name-1x2" >>"$out/$name.1x2"
  done
  python3 - "$name" "$(best <"$out/$name.1x1")" "$(best <"$out/$name.2x1")" \
    "$(best <"$out/$name.1x2")" "$out/$name-2x1/summary.json" "$out/$name-1x1/history.csv" \
    "$out/$name-2x1/history.csv" <<'PY'
import csv, json, sys
name, one, two, threads, summary, h1, h2 = sys.argv[1:]
a, b = list(csv.reader(open(h1))), list(csv.reader(open(h2)))
differ = {}
for ra, rb in zip(a[1:], b[1:]):
    for column, x, y in zip(a[0], ra, rb):
        if x != y:
            differ[column] = max(differ.get(column, 0.0), abs(float(x) - float(y)))
same = "identical" if not differ and len(a) == len(b) else "; ".join(
    f"{c} differs by ≤ {d:.1e}" for c, d in differ.items())
one, two, threads = float(one), float(two), float(threads)
s = json.load(open(summary))
entities = s["counts"]["particles"] + s["counts"]["elements"]
print(f"| {name} | {entities} | {s['steps']} | {one:.2f} | {two:.2f} | {threads:.2f} | "
      f"{one / two:.2f} | {threads / two:.2f} | {s['halo_bytes_per_entity_step']:.1f} | {same} |")
PY
}

echo "| case | entities | steps | 1 rank × 1 thread, s | 2 ranks × 1 thread, s | 1 rank × 2 threads, s | speed-up of 2 ranks | 2 threads / 2 ranks | halo bytes per entity-step | history of 2 ranks |"
echo "|---|---|---|---|---|---|---|---|---|---|"
measure fe_bar "$cases/bar_pressed_fe/case.yaml" --set bodies.bar.element_size=0.0005
measure sph_bar "$cases/bar_pressed_sph/case.yaml" --set bodies.bar.spacing=0.0005
# The Børvik shot at 303.5 m/s, the scene as it is (surface contact), by default its first
# 40 µs (the impact, the plug's shear band forming); at the coarse and the standard preset.
measure borvik_coarse "$cases/borvik_12mm/case.yaml" --set preset=coarse \
  --set projectile.velocity=303.5 --set time.end="$end"
measure borvik_standard "$cases/borvik_12mm/case.yaml" --set preset=standard \
  --set projectile.velocity=303.5 --set time.end="$end"
