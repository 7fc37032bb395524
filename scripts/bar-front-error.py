#!/usr/bin/env python3
"""Accuracy against cost on the pressed bar (docs/accuracy-vs-cost.md). For each run folder: the
`mid` probe's vz history against a reference run's (--reference, e.g. the finest FE bar),
interpolated in time, as rms(vz − vz_ref) / max|vz_ref| over the run; the arrival of the wave
front there (first time |vz| reaches 5% of its peak) against plane-wave theory, 50 mm / c_p
after the load reaches 5% of its plateau, c_p = sqrt((K + 4G/3)/rho); the peak |vz|; entities,
steps and wall time from summary.json. Prints CSV.
  scripts/bar-front-error.py --reference REF_RUN RUN_DIR...
"""
import argparse
import bisect
import csv
import json
import math

E, NU, RHO = 207e9, 0.3, 7830.0
K, G = E / (3 * (1 - 2 * NU)), E / (2 * (1 + NU))
C_P = math.sqrt((K + 4 * G / 3) / RHO)
PREDICTED = 0.05 * 0.25e-6 + 0.05 / C_P


def history(run):
    rows = list(csv.DictReader(open(f"{run}/history.csv")))
    return [float(r["time"]) for r in rows], [float(r["mid.vz"]) for r in rows]


def at(t, v, time):
    k = min(max(bisect.bisect_left(t, time), 1), len(t) - 1)
    return v[k - 1] + (v[k] - v[k - 1]) * (time - t[k - 1]) / (t[k] - t[k - 1])


parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--reference", required=True)
parser.add_argument("runs", nargs="+")
args = parser.parse_args()
t_ref, v_ref = history(args.reference)
scale = max(abs(x) for x in v_ref)

print("run,entities,steps,wall_s,rms_error_vs_reference,front_error_vs_theory,peak_vz_m_per_s")
for run in args.runs:
    t, v = history(run)
    rms = math.sqrt(sum((x - at(t_ref, v_ref, s)) ** 2 for s, x in zip(t, v)) / len(t)) / scale
    a = [abs(x) for x in v]
    peak = max(a)
    k = next(i for i, x in enumerate(a) if x >= 0.05 * peak)
    front = t[k] if k == 0 else t[k - 1] + (0.05 * peak - a[k - 1]) / (a[k] - a[k - 1]) * (t[k] - t[k - 1])
    s = json.load(open(f"{run}/summary.json"))
    entities = s["counts"]["particles"] + s["counts"]["elements"]
    print(f"{run},{entities},{s['steps']},{s['wall_s']:.3g},{rms:.4f},"
          f"{(front - PREDICTED) / PREDICTED:+.4f},{peak:.1f}")
