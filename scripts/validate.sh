#!/usr/bin/env bash
# The validation suite: every case with reference data run, compared with its references, and
# gathered on one page — the paper's bar cases (cases/bar_impact, cases/bar_pressed: 1D theory
# and the paper's values) and Børvik's plate (cases/borvik_12mm: the ballistic curve with its
# bisected limit against the experiments, and the plug's mass).
#
#   scripts/validate.sh [--preset coarse|standard|fine] [-o DIR] [-j THREADS]
#
# --preset sets the plate scenes' resolution (default standard; the bar cases have one). Writes
# DIR/<case>/ (each run's or sweep's own files and report), DIR/validation.csv (one row per
# compared quantity: case, quantity, prediction, reference, error, unit, source, whether the
# model was calibrated on that reference) and DIR/validation.html (the tables and the ballistic
# chart). Cost on 2 cores: about 2 h at the standard preset (the sweep: 7 shots and about 4
# bisection shots of 5–6 min), 30 min at the coarse one. Needs build/app/sphfem (or $SPHFEM).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; }
preset=standard
out=out/validation
threads=0
while [ $# -gt 0 ]; do
  case $1 in
  --preset) preset=${2:?--preset needs coarse, standard or fine}; shift 2 ;;
  -o) out=${2:?-o needs a folder}; shift 2 ;;
  -j) threads=${2:?-j needs a number of threads}; shift 2 ;;
  -h | --help) usage; exit 0 ;;
  *) echo "validate: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case $preset in coarse | standard | fine) ;; *)
  echo "validate: --preset: expected coarse, standard or fine, got '$preset'" >&2; exit 2 ;;
esac
case $threads in '' | *[!0-9]*)
  echo "validate: -j: expected a whole number of threads, got '$threads'" >&2; exit 2 ;;
esac
sphfem=${SPHFEM:-build/app/sphfem}
[ -x "$sphfem" ] || { echo "validate: $sphfem not found: build first (README, Build)" >&2; exit 2; }
mkdir -p "$out"

for c in bar_impact bar_pressed; do
  echo "validate: $c"
  "$sphfem" run "cases/$c/case.yaml" -o "$out/$c" -q --threads "$threads"
done
echo "validate: borvik_12mm, preset $preset (the ballistic curve and its limit)"
"$sphfem" sweep cases/borvik_12mm/case.yaml -o "$out/borvik_12mm" --bisect -j "$threads" \
  --set "preset=$preset" \
  --reference cases/borvik_12mm/borvik_12mm_table3.csv --reference-columns v0,exp_vpr,spfem_vpr \
  --reference-labels 'experiment,paper SPH-FEM'
python3 scripts/validation-page.py "$out" --preset "$preset"
