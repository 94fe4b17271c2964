// load_description: what load/ read, validated as a whole, with its loops assembled and grouped.
#include "model/load_description.hpp"

#include "model/topology.hpp"
#include "model/validate.hpp"

namespace mbgen::gen {

Description load_description(const std::string& path, const LoadOptions& options) {
  Description d = read_description(path, options);
  validate_description(d);
  build_topology(d);
  return d;
}

}  // namespace mbgen::gen
