#!/usr/bin/env python3
"""Where a perforated plate's energy went: the internal energy (stress work and viscous heating)
of the SPH core's particles at one frame of a plate_impact run, by the region each particle
started in — the plug under the projectile, the shear band around its edge, the rest of the
core — and by depth through the thickness (four quarters, from the impact face), beside the
ring's internal energy from history.csv. The band's rear quarter is the last ligament: the
material that holds the plug last. Quarter-model runs give a quarter of the plate's energies.

    scripts/plate-energy.py OUT [--frame N] [--radius 0.01] [--thickness 0.012]

Needs python3 with VTK (Debian: /usr/bin/python3 with python3-vtk9). Prints a Markdown table
(J, and % of the plate's internal energy).
"""
import argparse
import csv
import glob
import math
import os
import sys

import vtk


def frame_file(run, frame):
    # One file per frame (sph_NNNNNN.vtu), or a distributed run's .pvtu naming its ranks' pieces.
    frames = os.path.join(run, "frames")
    files = sorted(glob.glob(os.path.join(frames, "sph_[0-9][0-9][0-9][0-9][0-9][0-9].vtu")))
    files += sorted(glob.glob(os.path.join(frames, "sph_[0-9][0-9][0-9][0-9][0-9][0-9].pvtu")))
    if not files:
        sys.exit(f"plate-energy: no particle frames in {run}/frames")
    return files[frame] if frame is not None else files[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run")
    parser.add_argument("--frame", type=int, help="frame index (default: the last)")
    parser.add_argument("--radius", type=float, default=0.01, help="projectile radius, m")
    parser.add_argument("--thickness", type=float, default=0.012, help="plate thickness, m")
    args = parser.parse_args()

    file = frame_file(args.run, args.frame)
    reader = (vtk.vtkXMLPUnstructuredGridReader() if file.endswith(".pvtu")
              else vtk.vtkXMLUnstructuredGridReader())
    reader.SetFileName(file)
    reader.Update()
    grid = reader.GetOutput()
    data = grid.GetPointData()
    u, h = data.GetArray("displacement"), data.GetArray("h")
    e, m = data.GetArray("internal_energy"), data.GetArray("mass")  # J/kg, kg
    points = grid.GetPoints()
    n = grid.GetNumberOfPoints()
    # The band: particles that started within one initial smoothing length of the projectile's
    # edge (the band the kernel resolves is 2h wide). Initial h: the smallest (no compression yet
    # where the core is untouched).
    h0 = min(h.GetValue(i) for i in range(n))
    cells = {}
    for i in range(n):
        x, d = points.GetPoint(i), u.GetTuple3(i)
        x0 = [x[k] - d[k] for k in range(3)]
        r0 = math.hypot(x0[0], x0[1])
        region = "plug" if r0 < args.radius - h0 else "band" if r0 <= args.radius + h0 else "core"
        quarter = min(3, max(0, int(-x0[2] / args.thickness * 4)))
        cells[(region, quarter)] = cells.get((region, quarter), 0.0) + e.GetValue(i) * m.GetValue(i)

    rows = list(csv.DictReader(open(os.path.join(args.run, "history.csv"))))
    ring = float(rows[-1]["body.plate_ring.internal"])
    core = sum(cells.values())
    plate = core + ring
    print(f"{args.run}: frame {os.path.basename(frame_file(args.run, args.frame))}, band "
          f"|r0 − {args.radius * 1e3:g} mm| ≤ h0 = {h0 * 1e3:.2f} mm; plate {plate:.1f} J "
          f"(core {core:.1f}, ring {ring:.1f})\n")
    print("| depth from the impact face | plug | band | rest of the core |")
    print("|---|---|---|---|")
    t = args.thickness * 1e3
    for q in range(4):
        line = [f"{q * t / 4:g}–{(q + 1) * t / 4:g} mm"]
        for region in ("plug", "band", "core"):
            value = cells.get((region, q), 0.0)
            line.append(f"{value:.1f} J ({100 * value / plate:.1f}%)")
        print("| " + " | ".join(line) + " |")
    totals = [sum(cells.get((region, q), 0.0) for q in range(4)) for region in ("plug", "band", "core")]
    print("| all | " + " | ".join(f"{v:.1f} J ({100 * v / plate:.1f}%)" for v in totals) + " |")
    print(f"\nring (hexahedra): {ring:.1f} J ({100 * ring / plate:.1f}%); the last ligament (band, "
          f"rear quarter): {cells.get(('band', 3), 0.0):.1f} J "
          f"({100 * cells.get(('band', 3), 0.0) / plate:.1f}% of the plate)")


if __name__ == "__main__":
    main()
