#!/usr/bin/env bash
# Memory of each rank of a distributed run (issue 28): the peak resident memory (/usr/bin/time,
# Debian package `time`) and, when heaptrack is installed, the peak heap of every rank, for the
# Børvik standard shot's first µs (50 189 particles and elements) and for bar_impact (1 000: what
# the libraries and MPI take), at 1, 2 and 4 ranks (oversubscribed). Prints a Markdown table with
# the bytes per entity over the bar's: what the model costs a rank. Every rank holds the whole
# model but for the elements' state and neighbour lists today (docs/scaling.md), so that figure
# falls only a little with the rank count; it should not grow with it.
#   bench/mpi_memory.sh [SPHFEM=build/app/sphfem] [OUT=/tmp/sphfem_mpi_memory] [RANKS="1 2 4"]
# About 2 min here.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sphfem=${1:-$here/../build/app/sphfem}
out=${2:-/tmp/sphfem_mpi_memory}
rank_counts=${3:-1 2 4}
cases=$here/../cases
mkdir -p "$out"
heaptrack=$(command -v heaptrack || true)

# One rank: its peak resident memory into TAG.rss.RANK, or (MODE=heap) its heap profile into
# TAG.heap.RANK.zst, in a run of its own (heaptrack's memory would count as the rank's).
printf '%s\n' '#!/usr/bin/env bash' \
  "if [[ \$MODE == heap ]]; then exec heaptrack -o \"$out/\$TAG.heap.\$OMPI_COMM_WORLD_RANK\" \"\$@\"; fi" \
  "exec /usr/bin/time -f %M -o \"$out/\$TAG.rss.\$OMPI_COMM_WORLD_RANK\" \"\$@\"" \
  >"$out/measure.sh"
chmod +x "$out/measure.sh"

run() { # mode tag ranks case-file keys...
  local mode=$1 tag=$2 n=$3 file=$4
  shift 4
  OMP_NUM_THREADS=1 TAG=$tag MODE=$mode mpirun -x TAG -x MODE --allow-run-as-root \
    --oversubscribe --bind-to none -np "$n" "$out/measure.sh" "$sphfem" run "$file" \
    -o "$out/$tag-run" -q --set output.frames=false --threads 1 "$@" >/dev/null 2>&1
}

rm -f "$out"/*.rss.* "$out"/*.heap.*
borvik=("$cases/borvik_12mm/case.yaml" --set preset=standard --set projectile.velocity=303.5
  --set time.end=1e-6 --set time.history_interval=1e-6)
for n in $rank_counts; do
  run rss "bar$n" "$n" "$cases/bar_impact/case.yaml"
  run rss "borvik$n" "$n" "${borvik[@]}"
  [[ -z "$heaptrack" ]] || run heap "borvik$n" "$n" "${borvik[@]}"
done

python3 - "$out" "$rank_counts" <<'PY'
import glob, json, re, subprocess, sys
out, rank_counts = sys.argv[1], sys.argv[2].split()
def by_rank(pattern, rank_at):
    return sorted(glob.glob(pattern), key=lambda f: int(f.split(".")[rank_at]))
def rss(tag):  # MB per rank, rank order
    return [int(open(f).read().split()[-1]) / 1024 for f in by_rank(f"{out}/{tag}.rss.*", -1)]
def heap(tag):  # MB per rank, from heaptrack's summary
    values = []
    for f in by_rank(f"{out}/{tag}.heap.*", -2):
        text = subprocess.run(["heaptrack_print", "-f", f, "--print-peaks=0",
                               "--print-allocators=0", "--print-temporary=0"],
                              capture_output=True, text=True).stdout
        m = re.search(r"peak heap memory consumption: ([0-9.]+)([KMG])", text)
        values.append(float(m.group(1)) * {"K": 1 / 1024, "M": 1, "G": 1024}[m.group(2)])
    return values
def entities(tag):
    c = json.load(open(f"{out}/{tag}-run/summary.json"))["counts"]
    return c["particles"] + c["elements"]
fmt = lambda xs: " / ".join(f"{x:.0f}" for x in xs) if xs else "—"
print("| ranks | Børvik, resident MB per rank | bar_impact, resident MB per rank | "
      "Børvik, heap MB per rank | KB per entity on each rank (resident, over the bar's) |")
print("|---|---|---|---|---|")
for n in rank_counts:
    b, s = rss(f"borvik{n}"), rss(f"bar{n}")
    per_entity = [(x - y) * 2**20 / 1000 / entities(f"borvik{n}") for x, y in zip(b, s)]
    print(f"| {n} | {fmt(b)} | {fmt(s)} | {fmt(heap(f'borvik{n}'))} | "
          + " / ".join(f"{x:.2f}" for x in per_entity) + " |")
PY
