#!/usr/bin/python3
"""The share of a picture's ink that one of its layers holds (issue 64's balance of the
layers): LAYER.png (terrain-render frame --layers mask,L) and PICTURE.png (the default
picture) at the same camera; ink is darkness, 1 - mean(R, G, B) / 255, summed over the
terrain (the pixels that are not the frame's background colour, the top-left pixel's, in
the layer's picture). Prints the share, 0..1.
Usage: ink_share.py LAYER.png PICTURE.png"""
import sys

import numpy as np
from osgeo import gdal


def rgb(path):
    return gdal.Open(path).ReadAsArray().astype(float)[:3]


def main():
    layer, picture = rgb(sys.argv[1]), rgb(sys.argv[2])
    background = np.all(layer == layer[:, :1, :1], axis=0)
    terrain = ~background
    ink = lambda a: (1 - a.mean(axis=0) / 255.0)[terrain].sum()  # noqa: E731
    total = ink(picture)
    print(f"{ink(layer) / total if total > 0 else 0.0:.3f}")


if __name__ == "__main__":
    main()
