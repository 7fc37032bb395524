#!/usr/bin/env bash
# Calibrates the fracture regularisation length L without ballistic data (docs/calibration.md):
# the punch test of cases/calibration_punch — a flat punch pushed at 20 m/s through a clamped
# 12 mm plate — in hexahedra (the reference: the damage law unscaled, as its material tests
# calibrated it) and in SPH particles at each spacing and length; L is where the SPH plate
# takes the reference's work to push the plug out.
#
#   scripts/calibrate.sh [--material FILE] [--spacings S,…] [--lengths L,…] [--reference-sizes E,…]
#                        [--reference RUN] [-o DIR] [-j THREADS]
#
# --material: the plate's material file (default cases/materials/weldox460e.yaml); --spacings:
# the SPH lattice spacings, m (default 0.0015,0.001,0.00075); --lengths: the L tried at each,
# m (default 0.0008,0.0012,0.0016); --reference-sizes: the hexahedra's sizes, m, finest last
# (default 0.001,0.00075,0.0005; each must divide 21 mm and 12 mm, as must the spacings; `none`:
# no hexahedral run); --reference: the run the others are matched to (default the finest
# hex_<size>; an sph_<spacing>_L<length> run transfers its L to the other spacings: the L at
# each that takes its work). Runs left by an earlier call in DIR are kept (delete a folder to
# rerun it). Writes DIR/<run>/,
# DIR/calibration.csv (one row per run: its peak force, travel at separation and work),
# DIR/calibration.json (L per spacing, interpolated, and the reference) and DIR/calibration.png
# (force against travel). Cost on 2 cores with the defaults: about 1.5 h. Needs
# build/app/sphfem (or $SPHFEM) and python3.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; }
material=$PWD/cases/materials/weldox460e.yaml
spacings=0.0015,0.001,0.00075
lengths=0.0008,0.0012,0.0016
sizes=0.001,0.00075,0.0005
reference=
out=out/calibration
threads=0
while [ $# -gt 0 ]; do
  case $1 in
  --material) material=$(realpath -m "${2:?--material needs a file}"); shift 2 ;;
  --spacings) spacings=${2:?--spacings needs a list}; shift 2 ;;
  --lengths) lengths=${2:?--lengths needs a list}; shift 2 ;;
  --reference-sizes) sizes=${2:?--reference-sizes needs a list}; shift 2 ;;
  --reference) reference=${2:?--reference needs a run folder name}; shift 2 ;;
  -o) out=${2:?-o needs a folder}; shift 2 ;;
  -j) threads=${2:?-j needs a number of threads}; shift 2 ;;
  -h | --help) usage; exit 0 ;;
  *) echo "calibrate: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -f "$material" ] || { echo "calibrate: --material: no such file '$material'" >&2; exit 2; }
[ "$sizes" = none ] && sizes=
for list in "$spacings" "$lengths" ${sizes:+"$sizes"}; do
  case $list in '' | *[!0-9.,e-]*)
    echo "calibrate: expected a comma-separated list of lengths in m, got '$list'" >&2; exit 2 ;;
  esac
done
[ -n "$reference" ] || [ -n "$sizes" ] || {
  echo "calibrate: --reference-sizes none needs --reference RUN" >&2; exit 2; }
case $threads in '' | *[!0-9]*)
  echo "calibrate: -j: expected a whole number of threads, got '$threads'" >&2; exit 2 ;;
esac
sphfem=${SPHFEM:-build/app/sphfem}
[ -x "$sphfem" ] || { echo "calibrate: $sphfem not found: build first (README, Build)" >&2; exit 2; }
mkdir -p "$out"

run() { # folder, case, --set arguments…
  local dir=$out/$1 case=$2
  shift 2
  if [ -f "$dir/summary.json" ]; then
    echo "calibrate: $dir kept (delete it to rerun)"
    return
  fi
  echo "calibrate: $dir"
  "$sphfem" run "cases/calibration_punch/$case" -o "$dir" -q --threads "$threads" \
    --set "materials.weldox460e.library=$material" "$@"
}
for e in ${sizes//,/ }; do
  run "hex_$e" hex.yaml --set "bodies.plate.element_size=$e"
done
for s in ${spacings//,/ }; do
  base=$(python3 -c "print($s / 2 + 0.00025)") # 0.25 mm above the particles' spheres
  for l in ${lengths//,/ }; do
    run "sph_${s}_L$l" sph.yaml --set "bodies.plate.spacing=$s" \
      --set "bodies.punch.geometry.cylinder.base=[0, 0, $base]" \
      --set "materials.weldox460e.damage.regularisation_length=$l"
  done
done
python3 scripts/calibration.py "$out" --reference "${reference:-hex_${sizes##*,}}"
