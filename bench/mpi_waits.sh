#!/usr/bin/env bash
# Where each rank of a distributed run spends its wall time (issue 28): perf samples every rank
# on the CPU clock (time, stalls included — what callgrind's instruction counts of
# mpi_instructions.sh do not show) with DWARF call graphs, for the coarse Børvik shot's first
# 40 µs on 2 ranks. Prints, per rank, the samples inside Simulation::step by the step's phase
# (the function the step called) and the samples spent in MPI by the sphfem call that waited —
# a rank waiting at a phase's exchange or reduction is waiting for the other's share of that
# phase. Needs perf (Debian: linux-perf) and a kernel that lets it sample (perf_event_paranoid
# ≤ 1, or root).
#   bench/mpi_waits.sh [SPHFEM=build/app/sphfem] [OUT=/tmp/sphfem_mpi_waits]
# About 1 min here.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
out=${2:-/tmp/sphfem_mpi_waits}
case_file=$here/../cases/borvik_12mm/case.yaml
mkdir -p "$out"
keys=(-q --set preset=coarse --set projectile.velocity=303.5 --set time.end=4e-5
  --set output.frames=false --set time.history_interval=1e-6 --threads 1)

"$sphfem" mesh "$case_file" -o "$out/run" "${keys[@]}" >/dev/null
cat >"$out/sample.sh" <<EOF
#!/usr/bin/env bash
exec perf record -q -e cpu-clock -F 250 --call-graph dwarf,16384 \
  -o "$out/rank\$OMPI_COMM_WORLD_RANK.perf" "\$@"
EOF
chmod +x "$out/sample.sh"
OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe --bind-to none -np 2 \
  "$out/sample.sh" "$sphfem" solve "$case_file" -o "$out/run" "${keys[@]}" >/dev/null
for r in 0 1; do
  perf script -i "$out/rank$r.perf" 2>/dev/null >"$out/rank$r.txt"
done

python3 - "$out" <<'PY'
import collections, re, sys
out = sys.argv[1]
frame = re.compile(r"\s*[0-9a-f]+ (.*?)(\+0x[0-9a-f]+)? \((.*)\)$")
def stacks(file):  # each sample's frames, innermost first: (function, object)
    sample = []
    for line in open(file, errors="replace"):
        if not line.strip():
            if sample:
                yield sample
            sample = []
        elif line[0] in " \t":
            m = frame.match(line.rstrip("\n"))
            if m:
                sample.append((m.group(1), m.group(3)))
    if sample:
        yield sample
def in_mpi(sample):
    name, lib = sample[0]
    return any(k in lib for k in ("libmpi", "open-pal", "mca_")) or "copy_to_iter" in name
def short(name):
    return re.sub(r"\(.*", "", name).replace("sphfem::", "")[:60]
for r in (0, 1):
    phases, waits, step = collections.Counter(), collections.Counter(), 0
    for s in stacks(f"{out}/rank{r}.txt"):
        names = [n for n, _ in s]
        at = [i for i, n in enumerate(names) if n.startswith("sphfem::Simulation::step")]
        if not at:
            continue
        step += 1
        phases[short(names[at[-1] - 1]) if at[-1] > 0 else "step itself"] += 1
        if in_mpi(s):  # the sphfem call that waited, and the step's code that made it
            calls = [n for n in names if n.startswith("sphfem::")]
            made = [n for n in calls if not n.startswith(("sphfem::ranks::",
                                                          "sphfem::HaloExchange::"))]
            waits[short(calls[0]) + " ← " + (short(made[0]) if made else "?")] += 1
    print(f"\nrank {r}: {step} samples in the step, {sum(waits.values())} in MPI "
          f"({100 * sum(waits.values()) / max(step, 1):.1f}%)\n")
    print("| phase (called by the step) | samples |\n|---|---|")
    for k, v in phases.most_common(8):
        print(f"| {k} | {v} |")
    print("\n| waiting in MPI at | samples |\n|---|---|")
    for k, v in waits.most_common(8):
        print(f"| {k} | {v} |")
PY
