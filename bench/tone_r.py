#!/usr/bin/python3
"""Tone fidelity of a line picture (issue 51; docs/terrain-render.md, "Hachures"): the
darkness of LINES.png (its ink, 0..1, over the terrain) blurred by a Gaussian of sigma
SIGMA pixels and normalized inside the terrain, against the darkness of SHADED.png (the
`shaded` layer at the same camera), Pearson r over the terrain's pixels at least half inside
the blurred terrain. Prints: r (against the shaded layer as it is), the ceiling (the shaded
layer blurred the same way against itself: the best any blurred ink can do), r_tone (both
blurred: tone against tone) and the ink share over the terrain.
Usage: tone_r.py LINES.png SHADED.png SIGMA"""
import sys

import numpy as np
from osgeo import gdal


def rgb(path):
    d = gdal.Open(path)
    return np.stack([d.GetRasterBand(b + 1).ReadAsArray().astype(float) / 255 for b in range(3)])


lines, shaded, sigma = rgb(sys.argv[1]), rgb(sys.argv[2]), float(sys.argv[3])
bg = np.array([0xdd, 0xe4, 0xec])[:, None, None] / 255
terrain = np.abs(shaded - bg).max(axis=0) > 0.02        # the shaded layer covers the terrain
ink = np.where(terrain, 1 - lines.mean(axis=0), 0)      # darkness of the line picture (white mask: 0)
r = int(3 * sigma)
k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
k /= k.sum()


def blur(a):
    a = np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 1, a)
    return np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 0, a)


w = blur(terrain.astype(float))
sel = terrain & (w > 0.5)
b = blur(ink) / np.maximum(w, 1e-6)
dark = 1 - shaded.mean(axis=0)
db = blur(np.where(terrain, dark, 0)) / np.maximum(w, 1e-6)
rr = np.corrcoef(b[sel], dark[sel])[0, 1]
ceiling = np.corrcoef(db[sel], dark[sel])[0, 1]
tone = np.corrcoef(b[sel], db[sel])[0, 1]
print(f"{rr:.3f} {ceiling:.3f} {tone:.3f} {ink[terrain].mean():.4f}")
