#!/usr/bin/python3
"""A plan-view map as QGIS draws it (issue 64's comparison): DEM's hillshade (QGIS's
hillshade renderer, light from the north-west at 45 degrees) under the line layers named,
each drawn black at its width, rendered by QGIS's map renderer to OUT.png at WIDTH pixels
over the DEM's extent.
Usage: QT_QPA_PLATFORM=offscreen bench/qgis_map_render.py DEM.tif OUT.png WIDTH GPKG:LAYER:WIDTH_MM..."""
import os
import sys

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from qgis.core import (QgsApplication, QgsHillshadeRenderer, QgsLineSymbol, QgsMapRendererSequentialJob,  # noqa: E402
                       QgsMapSettings, QgsRasterLayer, QgsSingleSymbolRenderer, QgsVectorLayer)
from qgis.PyQt.QtCore import QSize  # noqa: E402
from qgis.PyQt.QtGui import QColor  # noqa: E402


def render(dem_path, out, width, specs):
    dem = QgsRasterLayer(dem_path, "DEM")
    shade = QgsHillshadeRenderer(dem.dataProvider(), 1, 315, 45)
    shade.setOpacity(0.35)
    dem.setRenderer(shade)
    layers = []
    for spec in specs:
        path, name, mm = spec.rsplit(":", 2)
        v = QgsVectorLayer(f"{path}|layername={name}", name, "ogr")
        if not v.isValid():
            sys.exit(f"qgis_map_render: no layer {name} in {path}")
        v.setRenderer(QgsSingleSymbolRenderer(QgsLineSymbol.createSimple({"color": "0,0,0", "width": mm})))
        layers.append(v)
    s = QgsMapSettings()
    s.setLayers(layers + [dem])  # the first on top
    s.setDestinationCrs(dem.crs())
    s.setExtent(dem.extent())
    e = dem.extent()
    s.setOutputSize(QSize(width, round(width * e.height() / e.width())))
    s.setBackgroundColor(QColor(255, 255, 255))
    job = QgsMapRendererSequentialJob(s)
    job.start()
    job.waitForFinished()
    job.renderedImage().save(out, "png")


def main():
    app = QgsApplication([], False)
    app.initQgis()
    render(sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:])  # its layers gone before QGIS exits
    app.exitQgis()


if __name__ == "__main__":
    main()
