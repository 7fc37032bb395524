#!/usr/bin/env python3
"""The analysis of scripts/calibrate.sh: the punch test's force against travel, and L.

    scripts/calibration.py DIR [--reference RUN]

Reads each run folder of DIR (hex_<size>: the hexahedral reference; sph_<spacing>_L<length>: the
particles) — its history.csv: the punch's contact force contact.punch.fz (N, a quarter model: the
whole punch takes 4 ×) and its centre-of-mass velocity body.punch.vz, whose integral is the
travel. Per run: the peak force, the travel at it, the travel at separation (the first after the
peak where the force, averaged over 5 µs, falls below 10% of the peak) and the work to push the
plug out, W = ∫ F du over the whole run (the run goes on past separation). The reference is RUN
(default: the hex_ run of the smallest size); an sph_ run as the reference transfers its L to the
other spacings (the L at each that takes the same work). At each spacing, W is fitted by a
straight line in L over the lengths run, and L is where the line gives the reference's W (marked
extrapolated outside the lengths run). Writes DIR/calibration.csv, DIR/calibration.json, DIR/curves.csv
(run, travel_mm, force_kN) and, if sphfem is at hand, DIR/calibration.png. Standard library only.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

QUARTER = 4.0  # the cases are quarter models: the whole punch takes 4 × the computed force
SMOOTH = 5e-6  # s, the averaging window of the separation criterion
SEPARATED = 0.10  # of the peak force


def fail(message):
    sys.exit(f"calibration: {message}")


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for key in ("time", "contact.punch.fz", "body.punch.vz"):
        if not rows or key not in rows[0]:
            fail(f"{path}: no column {key} (not a run of cases/calibration_punch)")
    t = [float(r["time"]) for r in rows]
    force = [QUARTER * float(r["contact.punch.fz"]) for r in rows]
    v = [float(r["body.punch.vz"]) for r in rows]
    return t, force, v


def measure(t, force, v):
    """Peak force, travel at the peak, travel at separation, work; travel = −∫ vz dt."""
    travel = [0.0]
    for i in range(1, len(t)):
        travel.append(travel[-1] - 0.5 * (v[i] + v[i - 1]) * (t[i] - t[i - 1]))
    work = sum(0.5 * (force[i] + force[i - 1]) * (travel[i] - travel[i - 1])
               for i in range(1, len(t)))
    peak = max(range(len(t)), key=lambda i: force[i])
    separation = None
    lo = 0
    for i in range(len(t)):
        while t[i] - t[lo] > SMOOTH:
            lo += 1
        mean = sum(force[lo:i + 1]) / (i + 1 - lo)
        if i > peak and mean < SEPARATED * force[peak]:
            separation = travel[i]
            break
    return {"peak_force_N": force[peak], "travel_at_peak_m": travel[peak],
            "separation_travel_m": separation, "work_J": work, "travel": travel}


def fit_length(points, target):
    """L where the least-squares line W(L) through `points` [(L, W)] meets `target`."""
    n = len(points)
    if n < 2:
        return None, True
    mx = sum(p[0] for p in points) / n
    my = sum(p[1] for p in points) / n
    sxx = sum((p[0] - mx) ** 2 for p in points)
    if sxx == 0:
        return None, True
    slope = sum((p[0] - mx) * (p[1] - my) for p in points) / sxx
    if slope == 0:
        return None, True
    length = mx + (target - my) / slope
    lengths = [p[0] for p in points]
    return length, not (min(lengths) <= length <= max(lengths))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir")
    parser.add_argument("--reference",
                        help="the reference run's folder name, hex_… or sph_… (default: finest hex_)")
    args = parser.parse_args()
    if not os.path.isdir(args.dir):
        fail(f"{args.dir}: no such folder")
    runs = {}
    for name in sorted(os.listdir(args.dir)):
        hex_run = re.fullmatch(r"hex_([0-9.e-]+)", name)
        sph_run = re.fullmatch(r"sph_([0-9.e-]+)_L([0-9.e-]+)", name)
        history = os.path.join(args.dir, name, "history.csv")
        if not (hex_run or sph_run) or not os.path.isfile(history):
            continue
        t, force, v = read_history(history)
        m = measure(t, force, v)
        m["force"] = force
        m["kind"] = "hex" if hex_run else "sph"
        m["size_m"] = float((hex_run or sph_run).group(1))
        m["length_m"] = float(sph_run.group(2)) if sph_run else None
        runs[name] = m
    hexes = sorted((m["size_m"], name) for name, m in runs.items() if m["kind"] == "hex")
    if not hexes and not args.reference:
        fail(f"{args.dir}: no hex_<size> run with a history.csv (the reference; or name one "
             "with --reference)")
    reference = args.reference or hexes[0][1]
    if reference not in runs:
        fail(f"--reference {reference}: no such run with a history.csv in {args.dir}")
    ref = runs[reference]

    with open(os.path.join(args.dir, "calibration.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["run", "kind", "size_m", "length_m", "peak_force_N", "travel_at_peak_m",
                    "separation_travel_m", "work_J", "work_vs_reference"])
        for name, m in runs.items():
            w.writerow([name, m["kind"], m["size_m"], m["length_m"] or "",
                        f"{m['peak_force_N']:.6g}", f"{m['travel_at_peak_m']:.6g}",
                        "" if m["separation_travel_m"] is None else
                        f"{m['separation_travel_m']:.6g}",
                        f"{m['work_J']:.6g}", f"{m['work_J'] / ref['work_J']:.4f}"])
    with open(os.path.join(args.dir, "curves.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["run", "travel_mm", "force_kN"])
        for name, m in runs.items():
            for u, F in zip(m["travel"], m["force"]):
                w.writerow([name, f"{u * 1e3:.5g}", f"{F * 1e-3:.5g}"])

    spacings = {}
    for name, m in runs.items():
        if m["kind"] == "sph":
            spacings.setdefault(m["size_m"], []).append((m["length_m"], m["work_J"]))
    result = {"reference": {"run": reference,
                            **{k: v for k, v in ref.items() if k not in ("travel", "force")}},
              "criterion": "the SPH plate's work to push the plug out equals the reference's",
              "spacings": []}
    print(f"calibration: reference {reference}: peak {ref['peak_force_N'] * 1e-3:.1f} kN, "
          f"work {ref['work_J']:.1f} J")
    for spacing, points in sorted(spacings.items()):
        length, outside = fit_length(sorted(points), ref["work_J"])
        result["spacings"].append({"spacing_m": spacing, "runs": sorted(points),
                                   "length_m": length, "extrapolated": outside})
        text = "none (one length run)" if length is None else f"{length * 1e3:.3g} mm"
        print(f"calibration: spacing {spacing * 1e3:g} mm: L = {text}"
              f"{' (extrapolated)' if outside and length is not None else ''}")
    with open(os.path.join(args.dir, "calibration.json"), "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    sphfem = os.environ.get("SPHFEM", os.path.join(os.path.dirname(__file__), "..", "build", "app",
                                                   "sphfem"))
    if os.access(sphfem, os.X_OK):
        subprocess.run([sphfem, "post", "chart", os.path.join(args.dir, "curves.csv"), "-o",
                        os.path.join(args.dir, "calibration.png"), "--x", "travel_mm", "--y",
                        "force_kN", "--group", "run"], check=True, stdout=subprocess.DEVNULL)


if __name__ == "__main__":
    main()
