// load_description: what load/ read, validated as a whole, with its loops assembled and grouped.
#include "model/load_description.hpp"

#include "model/reduce_model.hpp"
#include "model/topology.hpp"
#include "model/validate.hpp"

namespace mbgen::gen {

// The pipeline from a file to a model with its loops, each stage a function of the last one's
// value: read (load/), reduce (the scene's lock, merge_below and loops, before the checks see
// the model), validate (checks only), and the topology (closures, assembly, sub-systems).
Description load_description(const std::string& path, const LoadOptions& options) {
  Description d = read_description(path, options);
  if (options.reduce) d = reduce_model(std::move(d));
  validate_description(d);
  return build_topology(std::move(d));
}

}  // namespace mbgen::gen
