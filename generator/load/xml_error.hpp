#pragma once
// The LoadError for an XML file tinyxml2 could not parse (URDF, MJCF and SDFormat alike): the line, the
// problem in words, and a fix that fits it.
#include <string>

#include "load/load_error.hpp"

namespace tinyxml2 {
class XMLDocument;
}

namespace mbgen::gen {

/// `doc` failed to parse `path`: "malformed XML: mismatched element (XMLElement name=inertial)".
/// Nesting deeper than tinyxml2's limit (TINYXML2_MAX_ELEMENT_DEPTH) says so.
LoadError xml_parse_error(const std::string& path, const tinyxml2::XMLDocument& doc);

}  // namespace mbgen::gen
