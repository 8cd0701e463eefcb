"""The Processing provider 'terrain': the toolkit's algorithms."""
from qgis.core import QgsProcessingProvider

from .algorithms import DrainageAlgorithm, PenAndInkMapAlgorithm, RenderAlgorithm


class TerrainProvider(QgsProcessingProvider):
    def id(self):
        return "terrain"

    def name(self):
        return "Pen-and-ink terrain"

    def longName(self):  # noqa: N802 (QGIS's name)
        return "Pen-and-ink terrain: DEMs to pen-and-ink maps, views and drainage layers"

    def loadAlgorithms(self):  # noqa: N802
        for algorithm in (PenAndInkMapAlgorithm(), RenderAlgorithm(), DrainageAlgorithm()):
            self.addAlgorithm(algorithm)
