#!/bin/sh
# Draws the charts of docs/ from the measured tables in docs/charts/*.csv with `sphfem post
# chart` (the tables are filled by the runs each page describes).
#   scripts/docs-charts.sh [SPHFEM]        (default: build/app/sphfem)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
sphfem=${1:-$here/build/app/sphfem}
d=$here/docs/charts
chart() { "$sphfem" post chart "$@"; }

chart "$d/accuracy-vs-cost.csv" -o "$d/accuracy-vs-cost.png" --x wall_s --y error_pct \
  --group model --log-x --log-y --title "Error against wall time (2 threads), coarse to fine" \
  --x-label "wall time (s)" --y-label "error against the reference (%)"
chart "$d/h-factor.csv" -o "$d/h-factor.png" --x h_factor --y rms_error_pct --group series \
  --log-y --title "bar_pressed_sph: the smoothing length factor" \
  --x-label "h / particle spacing" --y-label "mid probe vz, rms against the finest FE bar (%)"
chart "$d/step-factor.csv" -o "$d/step-factor.png" --x step_factor --y error_pct \
  --group series --log-y --title "bar_pressed: the step factor" \
  --x-label "step factor (sph.cfl, time.cfl)" --y-label "error (%)"
chart "$d/stability-step-factor.csv" -o "$d/stability-step-factor.png" --x step_factor \
  --y largest_error_pct --group series --log-y --title "Energy balance against the step factor" \
  --x-label "step factor" --y-label "largest energy balance error (%)"
chart "$d/stability-speed.csv" -o "$d/stability-speed.png" --x speed_m_per_s \
  --y largest_error_pct --group series --log-x --log-y \
  --title "Energy balance against the impact speed" --x-label "impact speed (m/s)" \
  --y-label "largest energy balance error (%)"
