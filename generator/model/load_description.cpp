// load_description: what load/ read, validated as a whole, with its loops assembled and grouped.
#include "model/load_description.hpp"

#include "model/reduce_model.hpp"
#include "model/topology.hpp"
#include "model/validate.hpp"

namespace mbgen::gen {

Description load_description(const std::string& path, const LoadOptions& options) {
  Description d = read_description(path, options);
  if (options.reduce) reduce_model(d);  // the scene's lock and merge_below, before the checks see the model
  validate_description(d);
  build_topology(d);
  return d;
}

}  // namespace mbgen::gen
