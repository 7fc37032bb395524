#!/usr/bin/python3
"""Draws a decomposition written by `sphfem partition` (OUT/partition.vtu and
OUT/partition_particles.vtu) as a PNG coloured by rank, in a square window of side W metres
from the model's lowest x and y corner: above, the view from −z (each element's and particle's
x–y extent painted, lowest last: the plate's distal face, not the projectile); below, the view from −y of the band of height W centred on
the particles (front-most last). A particle is painted as a square of side h/1.2 (the lattice
spacing of the default h factor). Needs VTK's Python module (Debian: python3-vtk9) to read the
files; the PNG is written with zlib alone.
    bench/partition_picture.py OUT PICTURE.png [W=0.04] [pixels=400]"""
import struct
import sys
import zlib

import vtk

COLOURS = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
           (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207)]


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def boxes(out):
    """(lo, hi, rank) of every element and particle."""
    result = []
    mesh = read(out + "/partition.vtu")
    rank = mesh.GetCellData().GetArray("rank")
    for c in range(mesh.GetNumberOfCells()):
        b = mesh.GetCell(c).GetBounds()
        result.append(((b[0], b[2], b[4]), (b[1], b[3], b[5]), int(rank.GetValue(c))))
    particles = read(out + "/partition_particles.vtu")
    if particles.GetNumberOfPoints() > 0:
        rank = particles.GetPointData().GetArray("rank")
        h = particles.GetPointData().GetArray("h")
        for i in range(particles.GetNumberOfPoints()):
            x, half = particles.GetPoint(i), h.GetValue(i) / 2.4
            result.append((tuple(x[d] - half for d in range(3)),
                           tuple(x[d] + half for d in range(3)), int(rank.GetValue(i))))
    return result, particles


def png(path, width, height, pixels):
    raw = b"".join(b"\x00" + bytes(row) for row in pixels)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    out, picture = sys.argv[1], sys.argv[2]
    window = float(sys.argv[3]) if len(sys.argv) > 3 else 0.04
    n = int(sys.argv[4]) if len(sys.argv) > 4 else 400
    items, particles = boxes(out)
    x0 = min(lo[0] for lo, _, _ in items)
    y0 = min(lo[1] for lo, _, _ in items)
    zs = [particles.GetPoint(i)[2] for i in range(particles.GetNumberOfPoints())]
    zc = sum(zs) / len(zs) if zs else sum(lo[2] + hi[2] for lo, hi, _ in items) / (2 * len(items))
    gap = 8
    scale = n / window
    pixels = [[255] * (3 * n) for _ in range(2 * n + gap)]

    def paint(u0, u1, v0, v1, row0, colour):  # u right, v up, in window coordinates (m)
        c0, c1 = max(0, int(u0 * scale)), min(n, int(u1 * scale + 0.999))
        r0, r1 = max(0, int((window - v1) * scale)), min(n, int((window - v0) * scale + 0.999))
        for r in range(r0, r1):
            row = pixels[row0 + r]
            for c in range(c0, c1):
                row[3 * c:3 * c + 3] = colour

    for lo, hi, rank in sorted(items, key=lambda item: -item[0][2]):  # from below: lowest last
        paint(lo[0] - x0, hi[0] - x0, lo[1] - y0, hi[1] - y0, 0, COLOURS[rank % len(COLOURS)])
    for lo, hi, rank in sorted(items, key=lambda item: -item[0][1]):  # from −y: front last
        paint(lo[0] - x0, hi[0] - x0, lo[2] - zc + window / 2, hi[2] - zc + window / 2, n + gap,
              COLOURS[rank % len(COLOURS)])
    png(picture, n, 2 * n + gap, pixels)


if __name__ == "__main__":
    main()
