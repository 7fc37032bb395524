#!/usr/bin/env bash
# Strong and weak scaling of the domain decomposition, from `sphfem partition` (issue 28): how
# evenly RCB shares the cost and what each rank would receive every step, at 1–64 ranks. No run
# is made: the counts are the decomposition's, the bytes a model of them (below). Prints two
# tables (Markdown) and leaves each census in OUT/.
#   bench/partition_scaling.sh [SPHFEM=build/app/sphfem] [OUT=/tmp/sphfem_partition_scaling]
#
# Bytes a rank receives per step, modelled from what the pair loops read of a neighbour
# (solver/sph/sph_update.cpp): a ghost point's kinematic state before the kinematics loop
# (x, v, m, ρ, h and its body, group and kill flags: 10 values) and its stress terms before the
# force loop (σCᵀ/ρ², the artificial stress R: 9 + 9, the sound speed, the Balsara factor and
# the mid-step position: 5), 33 × 8 B = 264 B; a foreign node's partial force and mass go to its
# owner and the sum comes back, 2 × 4 × 8 B = 64 B.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
out=${2:-/tmp/sphfem_partition_scaling}
mkdir -p "$out"

summarise() { # partition.json → one Markdown row
  python3 - "$1" "$2" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
parts = j["parts"]
n = len(parts)
own = [p["particles"] + p["elements"] for p in parts]
recv = [264 * p["ghost_points"] + 64 * p["foreign_nodes"] for p in parts]
halo = [p["halo_fraction"] for p in parts]
print(f"| {sys.argv[2]} | {n} | {sum(own) / n:.0f} | {j['imbalance']:.4f} | "
      f"{sum(halo) / n:.3f} | {max(halo):.3f} | "
      f"{sum(recv) / sum(own):.1f} | {max(r / o for r, o in zip(recv, own)):.1f} |")
PY
}

header() {
  echo "| $1 | ranks | entities per rank | imbalance | halo fraction mean | max | bytes per entity-step mean | max |"
  echo "|---|---|---|---|---|---|---|---|"
}

echo "Strong scaling: the Børvik standard quarter shot (cases/borvik_12mm/case.yaml)"
header "model"
for n in 1 2 3 4 8 16 32 64; do
  "$sphfem" partition "$here/../cases/borvik_12mm/case.yaml" -o "$out/borvik" -n "$n" -q
  cp "$out/borvik/partition.json" "$out/borvik_$n.json"
  summarise "$out/borvik_$n.json" "Børvik standard"
done

echo
echo "Weak scaling: one 10 × 10 mm unit of bench/cases/weak_plate.yaml per rank, the plate grown in x and y"
header "plate (units x × y)"
for layout in 1:1:1 2:2:1 4:2:2 8:4:2 16:4:4 32:8:4 64:8:8; do
  IFS=: read -r n nx ny <<<"$layout"
  x=$(python3 -c "print(0.01 * $nx)")
  y=$(python3 -c "print(0.01 * $ny)")
  "$sphfem" partition "$here/cases/weak_plate.yaml" -o "$out/plate_$n" -n "$n" -q \
    --set "bodies.plate_fe.geometry.box.max=[$x, $y, 0.005]" \
    --set "bodies.plate_sph.geometry.box.max=[$x, $y, 0.01]"
  summarise "$out/plate_$n/partition.json" "$nx × $ny"
done
