#!/usr/bin/python3
"""The QGIS Processing provider 'terrain' (qgis/terrain_processing), headless with PyQGIS:
each algorithm run as processing.run on real DEMs (MSH, the Michigamme LiDAR sample) gives
the files the same commands give from a shell, its layers valid, in the DEM's CRS, styled;
QGIS's progress bar moves, cancel leaves no output, a tool's error is its one line.
Exit 77 (ctest: skipped) where PyQGIS is missing. With TERRAIN_QGIS_SHOTS=DIR it also saves
QGIS's own render of the styled map layers over a hillshade (docs/qgis.md's pictures).

Usage: processing_test.py REPO_ROOT BIN_DIR DATA_DIR"""
import os
import shutil
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
try:
    from qgis.core import (QgsApplication, QgsProcessingContext, QgsProcessingException,
                           QgsProcessingFeedback, QgsProject, QgsRasterLayer, QgsSymbolLayer,
                           QgsVectorLayer)
except ImportError:
    print("skipped: PyQGIS (python3-qgis) is not installed")
    sys.exit(77)

REPO, BIN, DATA = sys.argv[1:4]
os.environ["TERRAIN_BIN"] = BIN
FAILURES = []
# Every file of the run, QGIS's own temporary folders (processing_*, qt_temp*) included,
# under one scratch folder removed at the end.
scratch = tempfile.mkdtemp(prefix="terrain_qgis_test_")
os.environ["TMPDIR"] = scratch


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        FAILURES.append(what)


app = QgsApplication([], False)
app.initQgis()
sys.path.append("/usr/share/qgis/python/plugins")
import processing  # noqa: E402
import qgis.utils  # noqa: E402
from processing.core.Processing import Processing  # noqa: E402

Processing.initialize()
# The plugin as a user installs it: the zip scripts/make-qgis-plugin.sh makes, unpacked
# into a plugin folder, loaded and started by QGIS's own plugin loader.
plugins = os.path.join(scratch, "plugins")
subprocess.run([os.path.join(REPO, "scripts", "make-qgis-plugin.sh"),
                os.path.join(scratch, "plugin.zip")], check=True, capture_output=True)
subprocess.run(["python3", "-m", "zipfile", "-e", os.path.join(scratch, "plugin.zip"), plugins],
               check=True)
sys.path.insert(0, plugins)
qgis.utils.plugin_paths.insert(0, plugins)
check(qgis.utils.loadPlugin("terrain_processing") and
      qgis.utils.startProcessingPlugin("terrain_processing") and
      QgsApplication.processingRegistry().providerById("terrain") is not None,
      "the plugin zip loads and registers the provider 'terrain'")


LAST_CONTEXT = []


def run(alg, params, feedback=None):
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    LAST_CONTEXT[:] = [context]
    return processing.run(alg, params, context=context, feedback=feedback or QgsProcessingFeedback())


def shell(*commands):
    start = time.time()
    for c in commands:
        subprocess.run([os.path.join(BIN, c[0])] + c[1:], check=True, capture_output=True)
    return time.time() - start


# The colour each layer's style draws it with (libterrain LayerStyle, the callers').
STYLE_COLOURS = {"branches": "#1f3d8c", "basins": "#6e6e6e", "divides": "#784820",
                 "hachures": "#000000", "ridges": "#3c2814", "outline": "#000000"}


def check_layers(gpkg, names, dem, what, colours=None):
    colours = STYLE_COLOURS if colours is None else colours
    crs = QgsRasterLayer(dem, "dem").crs().authid()
    rows = [f["f_table_name"] for f in
            QgsVectorLayer(f"{gpkg}|layername=layer_styles", "s", "ogr").getFeatures()]
    for name in names:
        layer = QgsVectorLayer(f"{gpkg}|layername={name}", name, "ogr")
        check(layer.isValid() and layer.crs().authid() == crs and layer.featureCount() > 0,
              f"{what}: layer {name} valid in {crs}, {layer.featureCount()} features")
        # Opened as QGIS opens it, the layer is drawn with its style: its colour and, where
        # the style sets one, its width by a field.
        symbol = layer.renderer().symbol().symbolLayer(0)
        colour = symbol.strokeColor() if symbol.layerType() == "SimpleFill" else symbol.color()
        width = symbol.dataDefinedProperties().property(QgsSymbolLayer.PropertyStrokeWidth)
        check(rows.count(name) == 1 and colour.name() == colours.get(name, colour.name()),
              f"{what}: layer {name} styled ({colour.name()}"
              f"{', width ' + width.expressionString() if width.isActive() else ''})")


def pen_and_ink_map(dem, name):
    out = os.path.join(scratch, name + ".gpkg")
    start = time.time()
    result = run("terrain:penandinkmap", {"INPUT": dem, "OUTPUT": out})
    took = time.time() - start
    layers = result["LAYERS"]
    check(len(layers) >= 2 and "hachures" in layers and "branches" in layers,
          f"{name}: penandinkmap wrote {layers}")
    to_load = sorted(LAST_CONTEXT[0].layersToLoadOnCompletion().keys())
    check(to_load == sorted(f"{out}|layername={n}" for n in layers),
          f"{name}: every layer loaded into the project when the run ends")
    check_layers(out, layers, dem, name)
    # The same commands from a shell: the processing run's overhead (figures, no assertion).
    w = tempfile.mkdtemp(dir=scratch)
    m, d, g = (os.path.join(w, n) for n in ("m.ply", "m.dv", "m.gpkg"))
    shell_time = shell(["dem2mesh", dem, m], ["build-drainage", m, d],
                       ["terrain-inspect", "export", m, "--to", "gpkg", "-o", g, "--dv", d],
                       ["terrain-inspect", "export", d, "--to", "gpkg", "-o", g, "--layers",
                        "branches"])
    print(f"figure: {name} penandinkmap {took:.2f} s in Processing, {shell_time:.2f} s from a "
          f"shell ({took / shell_time:.2f}x)")
    same = all(QgsVectorLayer(f"{out}|layername={n}", n, "ogr").featureCount() ==
               QgsVectorLayer(f"{g}|layername={n}", n, "ogr").featureCount() for n in layers)
    check(same, f"{name}: the same features as the shell's commands")
    return out


msh = os.path.join(DATA, "msh_2007_utm10n_10m.tif")
michigamme = os.path.join(DATA, "michigamme_sample.tif")
msh_map = pen_and_ink_map(msh, "msh")
michigamme_map = pen_and_ink_map(michigamme, "michigamme")

# terrain:drainage: the rivers, basins and divides, styled, in the DEM's CRS.
drainage = os.path.join(scratch, "drainage.gpkg")
result = run("terrain:drainage", {"INPUT": msh, "OUTPUT": drainage})
check(result["LAYERS"] == ["branches", "basins", "divides"], f"drainage: {result['LAYERS']}")
check_layers(drainage, result["LAYERS"], msh, "drainage")

# terrain:render: a top view through Processing is the PNG terrain-render writes from a
# shell with the same options (options from the table: VIEW, MAP_SCALE), with its CRS.
w = tempfile.mkdtemp(dir=scratch)
mesh, dv = os.path.join(w, "m.ply"), os.path.join(w, "m.dv")
shell(["dem2mesh", msh, mesh, "--spacing", "50"], ["build-drainage", mesh, dv])
view = os.path.join(scratch, "view.png")
views = ["auto", "top", "relief"]
run("terrain:render", {"MESH": mesh, "DV": dv, "VIEW": views.index("top"), "MAP_SCALE": 10,
                       "SIZE": "640x480", "OUTPUT": view})
direct = os.path.join(w, "direct.png")
shell(["terrain-render", "frame", mesh, dv, "-o", direct, "--view", "top", "--map-scale", "10",
       "--size", "640x480"])
from qgis.PyQt.QtGui import QImage  # noqa: E402
check(QImage(view) == QImage(direct) and not QImage(view).isNull(),
      "render: the PNG's pixels equal terrain-render's from a shell")
check(QgsRasterLayer(view, "v").crs().authid() == "EPSG:26910",
      "render: the map PNG carries its CRS (EPSG:26910)")
# The same map as a transparent GeoTIFF and as its lines in a GeoPackage.
tif, lines = os.path.join(scratch, "view.tif"), os.path.join(scratch, "view.gpkg")
for out in (tif, lines):
    run("terrain:render", {"MESH": mesh, "DV": dv, "VIEW": views.index("top"), "MAP_SCALE": 10,
                           "SIZE": "640x480", "BACKGROUND": "none", "OUTPUT": out})
raster = QgsRasterLayer(tif, "t")
check(raster.isValid() and raster.crs().authid() == "EPSG:26910" and raster.bandCount() == 4,
      "render: the map GeoTIFF in EPSG:26910 with 4 bands (RGBA)")
# In the frame's colours (#0d338c the creases', --crease-colour's default).
check_layers(lines, ["creases", "silhouettes", "hachures"], msh, "render's GeoPackage",
             {"creases": "#0d338c", "silhouettes": "#000000"})

# Progress: QGIS's bar moves through the run and ends at 100; cancel stops the tool and
# writes nothing.
seen = []
feedback = QgsProcessingFeedback()
feedback.progressChanged.connect(seen.append)
run("terrain:penandinkmap", {"INPUT": michigamme, "OUTPUT": os.path.join(scratch, "p.gpkg")},
    feedback)
# Values other than the steps' bounds (0, 25, 65, 90, 100) come from the tools' own bars.
inner = set(int(p) for p in seen) - {0, 25, 65, 90, 100}
check(len(inner) >= 3 and seen == sorted(seen) and seen[-1] == 100,
      f"progress: {len(inner)} values from the tools' bars, monotone, to 100")
canceled = os.path.join(scratch, "canceled.gpkg")
feedback = QgsProcessingFeedback()
feedback.progressChanged.connect(lambda p: p > 5 and feedback.cancel())
try:
    run("terrain:penandinkmap", {"INPUT": msh, "OUTPUT": canceled}, feedback)
    check(False, "cancel: the run was canceled")
except QgsProcessingException as e:
    check("canceled" in str(e) and not os.path.exists(canceled),
          f"cancel: '{e}', no output written")

# A tool's error is its one line: a DEM all of whose samples are no-data.
empty = os.path.join(scratch, "empty.tif")
subprocess.run(["gdal_translate", "-q", "-scale", "0", "10000", "0", "0", "-a_nodata", "0", msh,
                empty], check=True)
try:
    run("terrain:penandinkmap", {"INPUT": empty, "OUTPUT": os.path.join(scratch, "e.gpkg")})
    check(False, "error: a DEM with no data is refused")
except QgsProcessingException as e:
    text = str(e).strip()
    check(text.startswith("dem2mesh: error:") and "\n" not in text, f"error: one line: '{text}'")

shots = os.environ.get("TERRAIN_QGIS_SHOTS")
if shots:
    from qgis.core import (QgsBilinearRasterResampler, QgsHillshadeRenderer,
                           QgsMapRendererParallelJob, QgsMapSettings)
    from qgis.PyQt.QtCore import QSize
    from qgis.PyQt.QtGui import QColor
    for dem, gpkg, name in ((msh, msh_map, "msh"), (michigamme, michigamme_map, "michigamme")):
        hill = QgsRasterLayer(dem, "hillshade")
        hill.setRenderer(QgsHillshadeRenderer(hill.dataProvider(), 1, 315, 45))
        hill.resampleFilter().setZoomedInResampler(QgsBilinearRasterResampler())
        hill.resampleFilter().setZoomedOutResampler(QgsBilinearRasterResampler())
        hill.setOpacity(0.5)
        layers = [QgsVectorLayer(f"{gpkg}|layername={n}", n, "ogr")
                  for n in ("outline", "branches", "ridges", "hachures")]
        layers = [l for l in layers if l.isValid()] + [hill]
        settings = QgsMapSettings()
        settings.setLayers(layers)
        settings.setDestinationCrs(hill.crs())
        settings.setExtent(hill.extent())
        settings.setOutputSize(QSize(900, int(900 * hill.height() / hill.width())))
        settings.setBackgroundColor(QColor(255, 255, 255))
        job = QgsMapRendererParallelJob(settings)
        job.start()
        job.waitForFinished()
        job.renderedImage().save(os.path.join(shots, f"qgis_{name}_map.png"))
        print(f"saved {shots}/qgis_{name}_map.png")

print(f"{len(FAILURES)} failures")
sys.stdout.flush()
shutil.rmtree(scratch, ignore_errors=True)
app.exitQgis()
# Straight out: Python's own teardown after exitQgis frees QGIS's objects a second time
# (a segmentation fault at exit, PyQGIS's known one), which ctest would count as failed.
os._exit(1 if FAILURES else 0)
