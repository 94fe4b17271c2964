#pragma once
// Where a description's mesh reference points on this machine: `package://NAME/rest` through the
// user's NAME=DIR pairs (`--package-path`), then ROS_PACKAGE_PATH; `file://` and plain paths as
// files, relative ones against the description's folder.
#include <map>
#include <string>

namespace mbgen::mesh {

/// NAME -> DIR: `package://NAME/x` is DIR/x.
using PackagePaths = std::map<std::string, std::string>;

/// Parses `NAME=DIR` (one --package-path value); throws std::invalid_argument naming the value.
std::pair<std::string, std::string> parse_package_path(const std::string& value);

/// The file a mesh reference names. `package://NAME/x` or `model://NAME/x`: DIR/x for NAME=DIR in `packages`; else
/// P/NAME/x for the first folder P of ROS_PACKAGE_PATH (colon-separated) where that file
/// exists. Throws MeshError saying what was tried and how to fix it.
std::string resolve_mesh_path(const std::string& reference, const std::string& description_dir, const PackagePaths& packages);

}  // namespace mbgen::mesh
