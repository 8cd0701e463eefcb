"""QGIS plugin: the pen-and-ink terrain toolkit as Processing algorithms (provider 'terrain')."""


def classFactory(iface):  # noqa: N802 (QGIS's name)
    from .plugin import TerrainPlugin

    return TerrainPlugin()
