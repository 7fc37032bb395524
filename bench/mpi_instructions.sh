#!/usr/bin/env bash
# What each rank of a distributed run executes in the step, against one process (issue 28):
# valgrind's callgrind counts the instructions inside Simulation::step only (meshing, start-up
# and output excluded) for the coarse Børvik shot's first 10 µs at 1 rank and at 2 ranks.
# Instruction counts do not depend on the machine's load, so they show balance and duplicated
# work where wall times are noisy: a rank that executes more than half of the single process's
# count repeats work, two ranks that execute unlike counts are unbalanced. Prints a Markdown
# table: G instructions per phase (the functions named below, exclusive counts) and in all.
#   bench/mpi_instructions.sh [SPHFEM=build/app/sphfem] [OUT=/tmp/sphfem_mpi_instructions]
# About 2 min here (valgrind runs the step ≈ 50 × slower).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
out=${2:-/tmp/sphfem_mpi_instructions}
case_file=$here/../cases/borvik_12mm/case.yaml
mkdir -p "$out"
keys=(-q --set preset=coarse --set projectile.velocity=303.5 --set time.end=1e-5
  --set output.frames=false --set time.history_interval=1e-6 --threads 1)
grind=(valgrind -q --tool=callgrind --collect-atstart=no "--toggle-collect=sphfem::Simulation::step*")

"$sphfem" mesh "$case_file" -o "$out/one" "${keys[@]}" >/dev/null
"$sphfem" mesh "$case_file" -o "$out/two" "${keys[@]}" >/dev/null
OMP_NUM_THREADS=1 "${grind[@]}" --callgrind-out-file="$out/one.out" \
  "$sphfem" solve "$case_file" -o "$out/one" "${keys[@]}" >/dev/null
OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe --bind-to none -np 2 "${grind[@]}" \
  "--callgrind-out-file=$out/two.%q{OMPI_COMM_WORLD_RANK}.out" \
  "$sphfem" solve "$case_file" -o "$out/two" "${keys[@]}" >/dev/null

for f in one two.0 two.1; do
  callgrind_annotate --threshold=100 "$out/$f.out" >"$out/$f.txt"
done
python3 - "$out" <<'PY'
import re, sys
out = sys.argv[1]
phases = {  # phase: substrings of the function names (exclusive counts)
    "element update": ["update_elements", "hex8_gradient", "hex8_hourglass_shape",
                       "hex8_characteristic_length", "hex8_velocity_gradient", "jaumann_rotate",
                       "NodeGather::gather_forces"],
    "SPH pair loops": ["sph_forces", "particle_kinematics", "background_kinematics"],
    "neighbour search": ["NeighbourSearch::"],
    "mirror images": ["MirrorParticles::"],
    "background fill": ["BackgroundParticles::", "nodal_stress"],
    "halo copies": ["HaloExchange::"],
    "waiting in MPI": ["mca_btl_vader", "opal_progress", "ompi_sync_wait", "libmpi", "libopen-pal"],
}
def counts(name):
    total, per = 0, {p: 0 for p in phases}
    for line in open(f"{out}/{name}.txt"):
        m = re.match(r"\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)", line)
        if not m:
            continue
        n, what = int(m.group(1).replace(",", "")), m.group(2)
        if "PROGRAM TOTALS" in what:
            total = n
            continue
        for p, keys in phases.items():
            if any(k in what for k in keys):
                per[p] += n
                break
    return total, per
one, r0, r1 = counts("one"), counts("two.0"), counts("two.1")
print("| G instructions | one process | rank 0 | rank 1 | ranks / one process |")
print("|---|---|---|---|---|")
for p in phases:
    a, b, c = one[1][p] / 1e9, r0[1][p] / 1e9, r1[1][p] / 1e9
    ratio = f"{(b + c) / a:.2f}" if a > 0 else "—"
    print(f"| {p} | {a:.2f} | {b:.2f} | {c:.2f} | {ratio} |")
a, b, c = one[0] / 1e9, r0[0] / 1e9, r1[0] / 1e9
print(f"| the step, all | {a:.2f} | {b:.2f} | {c:.2f} | {(b + c) / a:.2f} |")
print(f"\nbusiest rank's work (waits excluded) against one process: "
      f"{max(b - r0[1]['waiting in MPI'] / 1e9, c - r1[1]['waiting in MPI'] / 1e9) / a:.3f}")
PY
