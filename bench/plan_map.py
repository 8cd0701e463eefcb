#!/usr/bin/python3
"""A plan-view hachure map against its DEM (issue 64's plan-map targets): MAP.gpkg's
`hachures` layer (terrain-inspect export MESH --to gpkg) over DEM.tif, on the DEM's grid
resampled to CELL metres (average). Prints, one "key: value" a line:
  ink share per slope class   the share of the cells of each class (degrees, from the
                              resampled DEM: gdaldem slope) that a hachure crosses
                              (gdal_rasterize, the lines burnt into the cell grid)
  ink ratio steep / moderate  ink share at >= 15 degrees over that at 5 .. 9.4
  fall line deviation         length-weighted mean angle (degrees) between each segment
                              and the DEM's fall line at its middle (the gradient of the
                              DEM at its own spacing, bilinear)
  crossings                   pairs of segments of two different hachures that cross
  gpkg bytes, vertices, hachures
Usage: plan_map.py MAP.gpkg DEM.tif [CELL]"""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
from osgeo import gdal, ogr

gdal.UseExceptions()


def main():
    gpkg, dem = sys.argv[1], sys.argv[2]
    cell = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    tmp = tempfile.mkdtemp()
    coarse, slope, ink = (os.path.join(tmp, n) for n in ("dem.tif", "slope.tif", "ink.tif"))
    subprocess.run(["gdalwarp", "-q", "-r", "average", "-tr", str(cell), str(cell), dem, coarse], check=True)
    subprocess.run(["gdaldem", "slope", "-q", coarse, slope], check=True)
    s = gdal.Open(slope)
    gt, w, h = s.GetGeoTransform(), s.RasterXSize, s.RasterYSize
    sl = s.GetRasterBand(1).ReadAsArray().astype(float)
    valid = sl >= 0  # gdaldem writes -9999 on the edge
    subprocess.run(["gdal_rasterize", "-q", "-burn", "1", "-init", "0", "-ot", "Byte", "-l", "hachures",
                    "-te", str(gt[0]), str(gt[3] + h * gt[5]), str(gt[0] + w * gt[1]), str(gt[3]),
                    "-ts", str(w), str(h), gpkg, ink], check=True)
    burnt_ds = gdal.Open(ink)  # kept: a band outlives no dataset
    burnt = burnt_ds.GetRasterBand(1).ReadAsArray() > 0
    classes = [(0, 2), (2, 5), (5, 9.4), (9.4, 15), (15, 25), (25, 90)]
    share = {}
    for lo, hi in classes:
        sel = valid & (sl >= lo) & (sl < hi)
        share[(lo, hi)] = burnt[sel].mean() if sel.any() else float("nan")
        print(f"ink share {lo:g}..{hi:g} deg: {share[(lo, hi)]:.4f} ({sel.sum()} cells)")
    under5 = valid & (sl < 5)
    print(f"ink share under 5 deg: {burnt[under5].mean():.4f}")
    steep = valid & (sl >= 15)
    print(f"ink ratio steep / moderate: {burnt[steep].mean() / max(share[(5, 9.4)], 1e-9):.2f}")

    # The fall line at the DEM's own spacing.
    d = gdal.Open(dem)
    dg = d.GetGeoTransform()
    z = d.GetRasterBand(1).ReadAsArray().astype(float)
    gy, gx = np.gradient(z, -dg[5], dg[1])  # per metre: gy = dz/dsouth, gx = dz/deast

    def fall(x, y):
        u, v = (x - dg[0]) / dg[1] - 0.5, (y - dg[3]) / dg[5] - 0.5
        i, j = int(math.floor(v)), int(math.floor(u))
        if i < 0 or j < 0 or i + 1 >= z.shape[0] or j + 1 >= z.shape[1]:
            return None
        a, b = v - i, u - j
        ex = (1 - a) * ((1 - b) * gx[i, j] + b * gx[i, j + 1]) + a * ((1 - b) * gx[i + 1, j] + b * gx[i + 1, j + 1])
        ey = (1 - a) * ((1 - b) * gy[i, j] + b * gy[i, j + 1]) + a * ((1 - b) * gy[i + 1, j] + b * gy[i + 1, j + 1])
        # ex = dz/deast; rows run south, so ey = dz/dsouth: downhill is (-ex, +ey) (east, north).
        return -ex, ey

    src = ogr.Open(gpkg)
    layer = src.GetLayerByName("hachures")
    lines, vertices, dev_sum, dev_len = [], 0, 0.0, 0.0
    for f in layer:
        g = f.GetGeometryRef()
        pts = [(g.GetX(k), g.GetY(k)) for k in range(g.GetPointCount())]
        vertices += len(pts)
        lines.append(pts)
        for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
            L = math.hypot(x1 - x0, y1 - y0)
            fl = fall(0.5 * (x0 + x1), 0.5 * (y0 + y1))
            if L == 0 or fl is None or math.hypot(*fl) < 1e-9:
                continue
            c = abs((x1 - x0) * fl[0] + (y1 - y0) * fl[1]) / (L * math.hypot(*fl))
            dev_sum += L * math.degrees(math.acos(min(1.0, c)))
            dev_len += L
    print(f"fall line deviation deg: {dev_sum / max(dev_len, 1e-9):.3f}")
    print(f"crossings: {crossings(lines)}")
    print(f"gpkg bytes: {os.path.getsize(gpkg)}")
    print(f"vertices: {vertices}")
    print(f"hachures: {len(lines)}")


def crossings(lines):
    """Pairs of segments of two different lines that properly cross (a grid of buckets)."""
    segs = [(k, p, q) for k, pts in enumerate(lines) for p, q in zip(pts, pts[1:])]
    if not segs:
        return 0
    size = 4 * max(1e-9, np.median([math.hypot(q[0] - p[0], q[1] - p[1]) for _, p, q in segs]))
    buckets = {}
    for i, (_, p, q) in enumerate(segs):
        for bx in range(int(math.floor(min(p[0], q[0]) / size)), int(math.floor(max(p[0], q[0]) / size)) + 1):
            for by in range(int(math.floor(min(p[1], q[1]) / size)), int(math.floor(max(p[1], q[1]) / size)) + 1):
                buckets.setdefault((bx, by), []).append(i)

    def orient(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    seen = set()
    for ids in buckets.values():
        for x in range(len(ids)):
            for y in range(x + 1, len(ids)):
                i, j = ids[x], ids[y]
                (ki, p1, q1), (kj, p2, q2) = segs[i], segs[j]
                if ki == kj or (i, j) in seen:
                    continue
                d1, d2 = orient(p2, q2, p1), orient(p2, q2, q1)
                d3, d4 = orient(p1, q1, p2), orient(p1, q1, q2)
                if d1 * d2 < 0 and d3 * d4 < 0:
                    seen.add((i, j))
    return len(seen)


if __name__ == "__main__":
    main()
