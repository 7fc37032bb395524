#!/usr/bin/env bash
# Strong and weak scaling of distributed runs (issue 28), measured on real runs at 1–8 ranks
# (oversubscribed beyond 2 on a 2-core machine, so judge the bytes and halos, not the times):
# per rank count the bytes the ranks sent each other per entity-step and the halo fraction of
# their shares (halo rows and nodes / own particles and nodes), both from summary.json, beside
# the partition census's halo fraction for the same cut (`sphfem partition`, the model behind
# bench/partition_scaling.sh). Prints two Markdown tables; runs are left in OUT/.
#   bench/mpi_scaling.sh [SPHFEM=build/app/sphfem] [OUT=/tmp/sphfem_mpi_scaling]
#                        [RANKS="1 2 3 4 8"] [STEPS_END=2e-6]
# Strong: the Børvik standard quarter shot (8 125 particles, 42 064 hexahedra), its first
# STEPS_END seconds. Weak: one 10 × 10 mm unit of bench/cases/weak_plate.yaml (8 851 entities)
# per rank, the plate grown in x, then y (1 × 1, 2 × 1, 3 × 1, 2 × 2, 4 × 2 units).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
out=${2:-/tmp/sphfem_mpi_scaling}
ranks_list=${3:-1 2 3 4 8}
end=${4:-2e-6}
mkdir -p "$out"
mpirun_=(mpirun --allow-run-as-root --oversubscribe --bind-to none)

row() { # label ranks run-dir partition.json → one Markdown row
  python3 - "$@" <<'PY'
import json, sys
label, n, run, census = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
s = json.load(open(f"{run}/summary.json"))
c = json.load(open(census))
entities = s["counts"]["particles"] + s["counts"]["elements"]
halo = s.get("halo_fraction", {"mean": 0, "max": 0})
print(f"| {label} | {n} | {entities / n:.0f} | {s['wall_s']:.2f} | "
      f"{s.get('halo_bytes_per_entity_step', 0):.1f} | {halo['mean']:.3f} | {halo['max']:.3f} | "
      f"{c['halo_fraction']['mean']:.3f} | {c['halo_fraction']['max']:.3f} |")
PY
}

header() {
  echo "| $1 | ranks | entities per rank | wall, s | bytes sent per entity-step | halo fraction mean | max | census mean | census max |"
  echo "|---|---|---|---|---|---|---|---|---|"
}

run_on() { # ranks case out keys...
  local n=$1 file=$2 dir=$3
  shift 3
  local keys=(-q --threads 1 --set output.frames=false "$@")
  if [[ $n == 1 ]]; then
    "$sphfem" run "$file" -o "$dir" "${keys[@]}" >/dev/null
  else
    OMP_NUM_THREADS=1 "${mpirun_[@]}" -np "$n" "$sphfem" run "$file" -o "$dir" "${keys[@]}" \
      >/dev/null
  fi
  "$sphfem" partition "$file" -o "$dir/census" -n "$n" -q "${@}"
}

echo "Strong scaling: the Børvik standard quarter shot, t = 0 to $end s"
header "model"
borvik=$here/../cases/borvik_12mm/case.yaml
for n in $ranks_list; do
  run_on "$n" "$borvik" "$out/borvik_$n" --set time.end="$end" --set time.history_interval="$end"
  row "Børvik standard" "$n" "$out/borvik_$n" "$out/borvik_$n/census/partition.json"
done

echo
echo "Weak scaling: one 10 × 10 mm unit of bench/cases/weak_plate.yaml per rank"
header "plate (units x × y)"
for n in $ranks_list; do
  case $n in
  1) nx=1 ny=1 ;; 2) nx=2 ny=1 ;; 3) nx=3 ny=1 ;; 4) nx=2 ny=2 ;; 8) nx=4 ny=2 ;;
  *) echo "mpi_scaling: no weak-scaling layout for $n ranks (1, 2, 3, 4, 8)" >&2 && exit 1 ;;
  esac
  x=$(python3 -c "print(0.01 * $nx)")
  y=$(python3 -c "print(0.01 * $ny)")
  run_on "$n" "$here/cases/weak_plate.yaml" "$out/plate_$n" \
    --set "bodies.plate_fe.geometry.box.max=[$x, $y, 0.005]" \
    --set "bodies.plate_sph.geometry.box.max=[$x, $y, 0.01]"
  row "$nx × $ny" "$n" "$out/plate_$n" "$out/plate_$n/census/partition.json"
done
