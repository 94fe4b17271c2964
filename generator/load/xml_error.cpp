#include "load/xml_error.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <cctype>

namespace mbgen::gen {

LoadError xml_parse_error(const std::string& path, const tinyxml2::XMLDocument& doc) {
  // tinyxml2's "Error=XML_ERROR_MISMATCHED_ELEMENT ErrorID=14 (0xe) Line number=4: XMLElement
  // name=inertial" as "mismatched element (XMLElement name=inertial)": the line is given apart.
  std::string name = doc.ErrorName();
  if (name.rfind("XML_ERROR_", 0) == 0) name = name.substr(10);
  if (name.rfind("XML_", 0) == 0) name = name.substr(4);
  for (char& c : name) c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string full = doc.ErrorStr();
  const std::size_t colon = full.find(": ");
  const std::string problem = colon == std::string::npos ? name : fmt::format("{} ({})", name, full.substr(colon + 2));
  const std::string fix =
      doc.ErrorID() == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED
          ? fmt::format("elements are nested deeper than the XML reader's limit of {} levels (a robot description "
                        "needs about 10): the file is generated wrong or is not a description",
                        TINYXML2_MAX_ELEMENT_DEPTH)
          : "repair the XML (an unclosed tag or stray character is the usual cause)";
  return LoadError(path, doc.ErrorLineNum(), "", fmt::format("malformed XML: {}", problem), fix);
}

}  // namespace mbgen::gen
