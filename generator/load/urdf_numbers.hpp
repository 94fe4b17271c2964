#pragma once
// Every numeric attribute mbgen reads from a URDF, checked in the XML, with its line, before
// urdfdom parses the file: urdfdom reads a bad number (<mass value="nan"/>, "abc", "1e400") as
// NaN, infinity or a silent 0, and a massless link is plausible and wrong. Non-numeric text, a
// non-finite value, an overflow, the wrong count of numbers and a zero joint axis are each a
// LoadError naming the file, the line, the link or joint, the attribute and the fix.
#include <string>
#include <vector>

namespace tinyxml2 {
class XMLElement;
}

namespace mbgen::gen {

/// Checks the attributes of every <link> and <joint> under `robot` (urdf_numeric_attributes).
void check_urdf_numbers(const std::string& path, const tinyxml2::XMLElement& robot);

/// The attributes checked, for the docs and the table-driven test: under <link> or <joint>,
/// the element path ("inertial/mass"), the attribute, how many numbers, an example value.
struct UrdfNumericAttribute {
  const char* owner;  ///< "link" or "joint"
  const char* path;
  const char* attribute;
  int count;
  const char* example;
};
const std::vector<UrdfNumericAttribute>& urdf_numeric_attributes();

}  // namespace mbgen::gen
