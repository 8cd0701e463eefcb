// QGIS styles (QML, the document QGIS saves a layer's symbology as) of the GeoPackage layers
// the toolkit writes: one simple symbol, its width in millimetres, fixed or set by an
// expression of the layer's fields (a data-defined property).
#include <fmt/format.h>

#include "terrain/gpkg.hpp"
#include "terrain/xml_text.hpp"

namespace terrain {

namespace {

std::string option(const char* name, const std::string& value) {
  return fmt::format(R"(<Option name="{}" type="QString" value="{}"/>)", name, xml_escaped(value));
}

// The data-defined width: QgsSymbolLayer's property "outlineWidth" (a line's width, a
// fill's outline) or "size" (a marker's), from the expression.
std::string data_defined(const char* property, const std::string& expression) {
  if (expression.empty()) return {};
  return fmt::format(
      R"(<data_defined_properties><Option type="Map"><Option name="name" type="QString" value=""/>)"
      R"(<Option name="properties" type="Map"><Option name="{}" type="Map">)"
      R"(<Option name="active" type="bool" value="true"/>)"
      R"(<Option name="expression" type="QString" value="{}"/>)"
      R"(<Option name="type" type="int" value="3"/></Option></Option>)"
      R"(<Option name="type" type="QString" value="collection"/></Option>)"
      R"(</data_defined_properties>)",
      property, xml_escaped(expression));
}

}  // namespace

std::string qgis_style_qml(const LayerStyle& s, OGRwkbGeometryType type) {
  const OGRwkbGeometryType flat = wkbFlatten(type);
  const std::string width = fmt::format("{:g}", s.width_mm);
  std::string symbol_type, layer;
  if (flat == wkbPoint || flat == wkbMultiPoint) {
    symbol_type = "marker";
    layer = R"(<layer class="SimpleMarker" enabled="1" locked="0" pass="0"><Option type="Map">)" +
            option("name", "circle") + option("color", s.colour) +
            option("outline_color", "255,255,255,255") + option("outline_width", "0.2") +
            option("outline_width_unit", "MM") + option("size", width) + option("size_unit", "MM") +
            "</Option>" + data_defined("size", s.width_expression) + "</layer>";
  } else if (flat == wkbPolygon || flat == wkbMultiPolygon) {
    symbol_type = "fill";
    layer = R"(<layer class="SimpleFill" enabled="1" locked="0" pass="0"><Option type="Map">)" +
            option("style", "no") + option("color", "0,0,0,0") + option("outline_color", s.colour) +
            option("outline_style", "solid") + option("outline_width", width) +
            option("outline_width_unit", "MM") + option("joinstyle", "round") + "</Option>" +
            data_defined("outlineWidth", s.width_expression) + "</layer>";
  } else {
    symbol_type = "line";
    layer = R"(<layer class="SimpleLine" enabled="1" locked="0" pass="0"><Option type="Map">)" +
            option("line_color", s.colour) + option("line_style", "solid") +
            option("line_width", width) + option("line_width_unit", "MM") +
            option("capstyle", "round") + option("joinstyle", "round") + "</Option>" +
            data_defined("outlineWidth", s.width_expression) + "</layer>";
  }
  return fmt::format(
      "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n"
      R"(<qgis version="3.22" styleCategories="Symbology">)"
      R"(<renderer-v2 type="singleSymbol" symbollevels="0" enableorderby="0" forceraster="0">)"
      R"(<symbols><symbol type="{}" name="0" alpha="1" clip_to_extent="1" force_rhr="0">)"
      "{}</symbol></symbols></renderer-v2></qgis>\n",
      symbol_type, layer);
}

}  // namespace terrain
