#!/usr/bin/python3
"""Daniel Huffman's QGIS Hachures script, run headless as a QGIS user runs it (issue 64's
comparison of plan-view hachure maps): "Hachure Generator.py" of
https://github.com/pinakographos/Hachures (not part of this repository: pass its path),
with its own parameters, on DEM in PyQGIS (Debian's python3-qgis and qgis, for its
Processing algorithms), the script's `iface.activeLayer()` being DEM. Writes its layer
"Main Hachures" to OUT.gpkg (layer `hachures`) and prints the script's wall time.
Usage: QT_QPA_PLATFORM=offscreen bench/qgis_hachures.py SCRIPT.py DEM.tif OUT.gpkg"""
import os
import sys
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.append("/usr/share/qgis/python/plugins")

from qgis.core import (Qgis, QgsApplication, QgsCoordinateTransformContext, QgsProject, QgsRasterLayer,  # noqa: E402
                       QgsVectorFileWriter)
import qgis.utils  # noqa: E402


def main():
    script, dem_path, out = sys.argv[1:4]
    app = QgsApplication([], False)
    app.initQgis()
    from processing.core.Processing import Processing
    Processing.initialize()
    dem = QgsRasterLayer(dem_path, "DEM")
    if not dem.isValid():
        sys.exit(f"qgis_hachures: cannot read {dem_path}")
    QgsProject.instance().addMapLayer(dem)

    class MessageBar:
        def pushMessage(self, title, text, level=Qgis.Info, *_):
            print(f"{title}: {text}", file=sys.stderr)

    class Iface:  # what the script asks of QGIS's window
        def activeLayer(self):
            return dem

        def messageBar(self):
            return MessageBar()

    qgis.utils.iface = Iface()
    namespace = {"__name__": "__main__"}
    exec("from qgis.core import *\nfrom qgis.gui import *\nfrom qgis.utils import iface", namespace)
    with open(script, encoding="utf-8") as f:
        code = compile(f.read(), script, "exec")
    t0 = time.perf_counter()
    exec(code, namespace)
    seconds = time.perf_counter() - t0
    layers = QgsProject.instance().mapLayersByName("Main Hachures")
    if not layers:
        sys.exit("qgis_hachures: the script made no layer 'Main Hachures'")
    o = QgsVectorFileWriter.SaveVectorOptions()
    o.driverName, o.layerName = "GPKG", "hachures"
    err = QgsVectorFileWriter.writeAsVectorFormatV3(layers[0], out, QgsCoordinateTransformContext(), o)
    if err[0] != QgsVectorFileWriter.NoError:
        sys.exit(f"qgis_hachures: cannot write {out}: {err}")
    print(f"script seconds: {seconds:.2f}")
    print(f"hachures: {layers[0].featureCount()}")
    app.exitQgis()


if __name__ == "__main__":
    main()
