// load_description: URDF plus extras into one Description.
#include "mbgen/gen/description.hpp"

namespace mbgen::gen {

Description load_description(const std::string& path, const LoadOptions& options) {
  Description d;
  d.description_file = path;
  d.base = options.base.value_or(BaseType::Fixed);
  d.model = load_urdf_model(path, d.base, d.warnings);
  return d;
}

}  // namespace mbgen::gen
