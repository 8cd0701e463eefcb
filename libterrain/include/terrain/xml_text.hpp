#pragma once
// Text for XML documents the toolkit writes by hand (GDAL's PAM sidecars, QGIS styles).
#include <cpl_conv.h>
#include <cpl_string.h>

#include <string>

namespace terrain {

// `s` as XML character data or an attribute value: GDAL's escaping (& < > " and controls).
inline std::string xml_escaped(const std::string& s) {
  char* e = CPLEscapeString(s.c_str(), int(s.size()), CPLES_XML);
  std::string out(e);
  CPLFree(e);
  return out;
}

}  // namespace terrain
