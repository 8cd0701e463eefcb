#!/usr/bin/python3
"""Does a line picture show the land's forms (issue 64)? The darkness of LINES.png (its ink,
0..1, over the terrain) against the darkness of SHADED.png (the `shaded` layer at the same
camera), both filtered the same way, Pearson r over the terrain's pixels at least 12 px in
from its outline:
  bandpass  a difference of Gaussians, sigma 3 px minus sigma 12 px: the ridges, flanks and
            valleys themselves, not the light's drift over the frame (a sheet of even ticks
            whose density follows the light scores near 0 here, well under a 12 px blur);
  r8        both blurred by a Gaussian of sigma 8 px (tone against tone).
Blurs are normalized by the blurred terrain (no dark rim from the background). Prints:
bandpass r8 ink_share.
Usage: bandpass_r.py LINES.png SHADED.png"""
import sys

import numpy as np
from osgeo import gdal


def rgb(path):
    d = gdal.Open(path)
    return np.stack([d.GetRasterBand(b + 1).ReadAsArray().astype(float) / 255 for b in range(3)])


def gauss(a, sigma):
    """A separable Gaussian by FFT along each axis (zero outside the frame)."""
    r = int(3 * sigma)
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    for axis in (0, 1):
        n = a.shape[axis] + 2 * r
        fk = np.fft.rfft(k, n)
        fa = np.fft.rfft(a, n, axis=axis)
        shape = [1, 1]
        shape[axis] = -1
        full = np.fft.irfft(fa * fk.reshape(shape), n, axis=axis)
        a = np.take(full, np.arange(r, r + a.shape[axis]), axis=axis)
    return a


def inner(mask, r):
    """The mask's pixels at least r px in from its outline (a box of 2r + 1 inside it)."""
    c = np.pad(mask.astype(np.int64), ((1, 0), (1, 0))).cumsum(0).cumsum(1)
    h, w = mask.shape
    y0, y1 = np.arange(h) - r, np.arange(h) + r + 1
    x0, x1 = np.arange(w) - r, np.arange(w) + r + 1
    ok_y = (y0 >= 0) & (y1 <= h)
    ok_x = (x0 >= 0) & (x1 <= w)
    Y0, Y1 = np.clip(y0, 0, h), np.clip(y1, 0, h)
    X0, X1 = np.clip(x0, 0, w), np.clip(x1, 0, w)
    s = c[Y1][:, X1] - c[Y0][:, X1] - c[Y1][:, X0] + c[Y0][:, X0]
    out = (s == (2 * r + 1) ** 2) & ok_y[:, None] & ok_x[None, :]
    return out


def main():
    lines, shaded = rgb(sys.argv[1]), rgb(sys.argv[2])
    bg = np.array([0xdd, 0xe4, 0xec])[:, None, None] / 255
    terrain = np.abs(shaded - bg).max(axis=0) > 0.02  # the shaded layer covers the terrain
    ink = np.where(terrain, 1 - lines.mean(axis=0), 0.0)
    dark = np.where(terrain, 1 - shaded.mean(axis=0), 0.0)
    t = terrain.astype(float)
    sel = inner(terrain, 12)
    if sel.sum() < 100:
        print("nan nan nan")
        return

    def blur(a, sigma):
        return gauss(a, sigma) / np.maximum(gauss(t, sigma), 1e-6)

    def r(a, b):
        a, b = a[sel], b[sel]
        if a.std() < 1e-12 or b.std() < 1e-12:
            return float("nan")
        return float(np.corrcoef(a, b)[0, 1])

    band_ink = blur(ink, 3) - blur(ink, 12)
    band_dark = blur(dark, 3) - blur(dark, 12)
    print(f"{r(band_ink, band_dark):.3f} {r(blur(ink, 8), blur(dark, 8)):.3f} {ink[terrain].mean():.4f}")


if __name__ == "__main__":
    main()
