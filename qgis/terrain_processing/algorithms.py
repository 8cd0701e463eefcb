"""The algorithms of the provider 'terrain'. Each runs the same commands a shell would
(docs/qgis.md lists them), in a temporary folder of its own, and writes its output whole."""
import json
import os
import shutil
import subprocess
import tempfile

from qgis.core import (
    QgsProcessingAlgorithm,
    QgsProcessingContext,
    QgsProcessingException,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterDefinition,
    QgsProcessingParameterEnum,
    QgsProcessingParameterFile,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
    QgsProcessingUtils,
    QgsVectorLayer,
)

from .tools import run_tool, tool_path

HACHURE_STYLES = ["lines", "rows"]
HACHURE_TONES = ["slope", "light"]


def dem_path(alg, parameters, context):
    layer = alg.parameterAsRasterLayer(parameters, "INPUT", context)
    if layer is None:
        raise QgsProcessingException("INPUT: no DEM raster layer given")
    path = layer.source().split("|")[0]
    if not os.path.isfile(path):
        raise QgsProcessingException(f"INPUT: '{path}' is not a file (the tools read DEM files)")
    return path


def river_area(alg, parameters, context):
    """MIN_AREA in square metres: as given, else 100 of the DEM's cells and at least 1 ha
    (TauDEM's customary threshold of 100 cells), so that a coarse DEM's rivers keep in
    proportion to it (Mandakini at 89 m: 79 ha, 693 rivers; at 1 ha, 61,607)."""
    if parameters.get("MIN_AREA") is not None:
        return alg.parameterAsDouble(parameters, "MIN_AREA", context)
    layer = alg.parameterAsRasterLayer(parameters, "INPUT", context)
    cell = 0.0
    if layer is not None and not layer.crs().isGeographic():
        cell = abs(layer.rasterUnitsPerPixelX() * layer.rasterUnitsPerPixelY())
    return max(1e4, 100 * cell)


def work_folder():
    """A folder of this run's own under QGIS's temporary folder (two runs never share one)."""
    return tempfile.mkdtemp(prefix="terrain_", dir=QgsProcessingUtils.tempFolder())


def gpkg_layers(path):
    """The layers of a GeoPackage but QGIS's layer_styles, in file order."""
    names = []
    layer = QgsVectorLayer(path, "x", "ogr")  # held while its provider is asked
    for sub in layer.dataProvider().subLayers():
        name = sub.split("!!::!!")[1]  # QgsDataProvider's sublayer separator
        if name != "layer_styles":
            names.append(name)
    return names


def finish_gpkg(temp, output, context):
    """The GeoPackage made in the work folder moved onto OUTPUT whole, its layers loaded into
    the project when the algorithm ends (each drawn with the style it carries)."""
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    shutil.move(temp, output)
    layers = gpkg_layers(output)
    for name in layers:
        context.addLayerToLoadOnCompletion(
            f"{output}|layername={name}",
            QgsProcessingContext.LayerDetails(name, context.project(), name))
    return layers


def river_area_parameter():
    return QgsProcessingParameterNumber(
        "MIN_AREA", "Rivers where at least this many square metres drain (empty: 100 of the "
        "DEM's cells, at least 1 ha)", QgsProcessingParameterNumber.Double, defaultValue=None,
        optional=True, minValue=0)


class TerrainAlgorithm(QgsProcessingAlgorithm):
    def group(self):
        return "Pen-and-ink terrain"

    def groupId(self):  # noqa: N802 (QGIS's name)
        return "terrain"

    def createInstance(self):  # noqa: N802
        return type(self)()

    def tr(self, text):
        return text

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802 (QGIS's name)
        work = work_folder()
        try:
            return self.process(parameters, context, feedback, work)
        finally:  # a failed or canceled run leaves nothing behind either
            shutil.rmtree(work, ignore_errors=True)


class PenAndInkMapAlgorithm(TerrainAlgorithm):
    """dem2mesh, build-drainage, then terrain-inspect export of the map's layers (hachures,
    ridge lines, the data's outline) and the rivers (branches) into one GeoPackage."""

    def name(self):
        return "penandinkmap"

    def displayName(self):  # noqa: N802
        return "Pen-and-ink map (DEM to styled map layers)"

    def shortHelpString(self):  # noqa: N802
        return ("A DEM to a GeoPackage of the pen-and-ink map's layers, each styled as the "
                "toolkit draws it: hachures (width by tone), ridge lines, the data's outline "
                "where the DEM has no-data, and the rivers (width by Strahler order). Runs "
                "dem2mesh, build-drainage and terrain-inspect export.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("INPUT", "DEM"))
        self.addParameter(QgsProcessingParameterEnum(
            "HACHURE_STYLE", "Hachures", HACHURE_STYLES, defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum(
            "HACHURE_TONE", "Hachure density by", HACHURE_TONES, defaultValue=0))
        self.addParameter(QgsProcessingParameterNumber(
            "SCALE", "Map scale, metres a pixel (0: the longer side 2048 pixels)",
            QgsProcessingParameterNumber.Double, defaultValue=0, minValue=0))
        self.addParameter(QgsProcessingParameterNumber(
            "MIN_ORDER", "Rivers of at least this Strahler order",
            QgsProcessingParameterNumber.Integer, defaultValue=1, minValue=1, maxValue=255))
        self.addParameter(river_area_parameter())
        self.addParameter(QgsProcessingParameterFileDestination(
            "OUTPUT", "Map layers", "GeoPackage (*.gpkg)"))

    def process(self, parameters, context, feedback, work):
        dem = dem_path(self, parameters, context)
        output = self.parameterAsFileOutput(parameters, "OUTPUT", context)
        mesh, dv, gpkg = (os.path.join(work, n) for n in ("dem.ply", "dem.dv", "map.gpkg"))
        run_tool("dem2mesh", [dem, mesh], feedback, (0, 25))
        run_tool("build-drainage", [mesh, dv], feedback, (25, 65))
        style = HACHURE_STYLES[self.parameterAsEnum(parameters, "HACHURE_STYLE", context)]
        tone = HACHURE_TONES[self.parameterAsEnum(parameters, "HACHURE_TONE", context)]
        args = [mesh, "--to", "gpkg", "-o", gpkg, "--dv", dv, "--hachure-style", style,
                "--hachure-tone", tone]
        scale = self.parameterAsDouble(parameters, "SCALE", context)
        if scale > 0:
            args += ["--scale", scale]
        run_tool("terrain-inspect", ["export"] + args, feedback, (65, 90))
        run_tool("terrain-inspect",
                 ["export", dv, "--to", "gpkg", "-o", gpkg, "--layers", "branches",
                  "--min-order", self.parameterAsInt(parameters, "MIN_ORDER", context),
                  "--min-area", river_area(self, parameters, context)],
                 feedback, (90, 100))
        layers = finish_gpkg(gpkg, output, context)
        return {"OUTPUT": output, "LAYERS": layers}


class DrainageAlgorithm(TerrainAlgorithm):
    """build-drainage in raster mode, then terrain-inspect export of its GIS layers."""

    def name(self):
        return "drainage"

    def displayName(self):  # noqa: N802
        return "Drainage layers (DEM to rivers, basins, divides)"

    def shortHelpString(self):  # noqa: N802
        return ("A DEM to a GeoPackage of its drainage: the rivers (branches, with their "
                "Strahler order and flow), the basins and the divides between them, styled. "
                "Runs build-drainage --raster (D8, TauDEM's codes) and terrain-inspect export.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("INPUT", "DEM"))
        self.addParameter(QgsProcessingParameterBoolean(
            "FILL", "Fill depressions first (priority flood)", defaultValue=True))
        self.addParameter(QgsProcessingParameterNumber(
            "MIN_ORDER", "Rivers of at least this Strahler order",
            QgsProcessingParameterNumber.Integer, defaultValue=1, minValue=1, maxValue=255))
        self.addParameter(river_area_parameter())
        self.addParameter(QgsProcessingParameterFileDestination(
            "OUTPUT", "Drainage layers", "GeoPackage (*.gpkg)"))

    def process(self, parameters, context, feedback, work):
        dem = dem_path(self, parameters, context)
        output = self.parameterAsFileOutput(parameters, "OUTPUT", context)
        dv, gpkg = os.path.join(work, "dem.dv"), os.path.join(work, "drainage.gpkg")
        args = ["--raster", dem, dv]
        if self.parameterAsBool(parameters, "FILL", context):
            args.append("--fill")
        run_tool("build-drainage", args, feedback, (0, 60))
        run_tool("terrain-inspect",
                 ["export", dv, "--to", "gpkg", "-o", gpkg, "--min-order",
                  self.parameterAsInt(parameters, "MIN_ORDER", context),
                  "--min-area", river_area(self, parameters, context)],
                 feedback, (60, 100))
        layers = finish_gpkg(gpkg, output, context)
        return {"OUTPUT": output, "LAYERS": layers}


_RENDER_OPTIONS = []  # the table, read once: QGIS makes an instance per dialog and run


def render_options():
    """The render option table (terrain-render --list-options=json), or [] when the tool is
    not found (the algorithm then says so when run)."""
    if not _RENDER_OPTIONS:
        try:
            text = subprocess.run([tool_path("terrain-render"), "--list-options=json"],
                                  capture_output=True, text=True, check=True, timeout=60).stdout
            _RENDER_OPTIONS.extend(json.loads(text))
        except (QgsProcessingException, OSError, subprocess.SubprocessError, ValueError):
            pass
    return _RENDER_OPTIONS


def parameter_name(option):
    return option["name"].upper().replace("-", "_")


# The table's options shown first; every other is an advanced parameter.
MAIN_OPTIONS = ("size", "layers", "view", "view-az", "view-alt", "map-scale", "exaggeration")


def as_number(text):
    """A default as a number, or None where it is a word ('auto': the tool decides)."""
    try:
        return float(text)
    except ValueError:
        return None


def option_parameter(o):
    """A Processing parameter for a row of the render option table."""
    name, text, default = parameter_name(o), o["name"] + ": " + o["help"], o["default"]
    kind = o["type"]
    if kind in ("NUMBER", "INTEGER"):
        number = (QgsProcessingParameterNumber.Double if kind == "NUMBER"
                  else QgsProcessingParameterNumber.Integer)
        p = QgsProcessingParameterNumber(name, text, number, optional=True,
                                         defaultValue=as_number(default))
        if o["min"] is not None:
            p.setMinimum(o["min"])
        if o["max"] is not None:
            p.setMaximum(o["max"])
    elif kind == "FLAG":
        p = QgsProcessingParameterBoolean(name, text, defaultValue=default == "true",
                                          optional=True)
    elif kind == "CHOICE" and default in o["choices"]:
        p = QgsProcessingParameterEnum(name, text, o["choices"],
                                       defaultValue=o["choices"].index(default), optional=True)
    else:  # LIST, COLOUR, WxH, E N Z, an open choice: as the command line writes them
        p = QgsProcessingParameterString(name, text, defaultValue=default, optional=True)
    if o["name"] not in MAIN_OPTIONS:
        p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
    return p


def option_arguments(alg, options, parameters, context):
    """The command line's options for the parameters given other than their defaults."""
    args = []
    for o in options:
        name = parameter_name(o)
        if name not in parameters or parameters[name] is None:
            continue
        kind, default = o["type"], o["default"]
        if kind == "FLAG":
            if alg.parameterAsBool(parameters, name, context) != (default == "true"):
                args.append("--" + o["name"])
            continue
        if kind == "CHOICE" and default in o["choices"]:
            value = o["choices"][alg.parameterAsEnum(parameters, name, context)]
        elif kind in ("NUMBER", "INTEGER"):
            number = alg.parameterAsDouble(parameters, name, context)
            value = f"{number:g}" if kind == "NUMBER" else str(int(number))
            if as_number(default) == number:
                continue
        else:
            value = alg.parameterAsString(parameters, name, context)
        if value == default or value == "":
            continue
        args += ["--" + o["name"]] + (value.split() if kind == "E N Z" else [value])
    return args


class RenderAlgorithm(TerrainAlgorithm):
    """terrain-render frame of a DEM (meshed and drained first) or of a mesh, its options
    those of terrain-render's option table."""

    def __init__(self):
        super().__init__()
        self.options = render_options()

    def name(self):
        return "render"

    def displayName(self):  # noqa: N802
        return "Render a view (PNG, GeoTIFF, SVG, PDF or a map's GeoPackage)"

    def shortHelpString(self):  # noqa: N802
        return ("A pen-and-ink view of a DEM or of a mesh: creases, silhouettes, hachures and "
                "ridge lines, as terrain-render frame draws it. A DEM is meshed (dem2mesh) and "
                "drained (build-drainage) first. Every render option is a parameter (most "
                "under Advanced), from terrain-render --list-options=json. A top view (view: "
                "top) is a map: a GeoTIFF or a PNG with its world file and CRS, or its lines "
                "as styled GeoPackage layers (.gpkg); background none makes it transparent.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("INPUT", "DEM", optional=True))
        self.addParameter(QgsProcessingParameterFile(
            "MESH", "or a mesh (.ply from dem2mesh)", extension="ply", optional=True))
        self.addParameter(QgsProcessingParameterFile(
            "DV", "and its drainage (.dv from build-drainage)", extension="dv", optional=True))
        for o in self.options:
            self.addParameter(option_parameter(o))
        self.addParameter(QgsProcessingParameterFileDestination(
            "OUTPUT", "View",
            "PNG (*.png);;GeoTIFF (*.tif);;SVG (*.svg);;PDF (*.pdf);;GeoPackage (*.gpkg)"))

    def process(self, parameters, context, feedback, work):
        if not self.options:
            tool_path("terrain-render")  # says where it was looked for
            raise QgsProcessingException("terrain-render --list-options=json gave no options")
        output = self.parameterAsFileOutput(parameters, "OUTPUT", context)
        mesh = self.parameterAsFile(parameters, "MESH", context)
        dv = self.parameterAsFile(parameters, "DV", context)
        if not mesh:
            if self.parameterAsRasterLayer(parameters, "INPUT", context) is None:
                raise QgsProcessingException("give a DEM (INPUT) or a mesh (MESH)")
            dem = dem_path(self, parameters, context)
            mesh, dv = os.path.join(work, "dem.ply"), os.path.join(work, "dem.dv")
            run_tool("dem2mesh", [dem, mesh], feedback, (0, 25))
            run_tool("build-drainage", [mesh, dv], feedback, (25, 60))
        args = ["frame", mesh] + ([dv] if dv else []) + ["-o", output]
        args += option_arguments(self, self.options, parameters, context)
        run_tool("terrain-render", args, feedback, (60, 100))
        return {"OUTPUT": output}
