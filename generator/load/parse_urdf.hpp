#pragma once
// urdfdom's view of a URDF file, parsed the way load_urdf_model parses it (with the <limit>
// elements urdfdom insists on added), for readers that need more than the tree (collision
// geometry). Throws LoadError when the file cannot be read or parsed.
#include <string>

#include <urdf_model/model.h>
#include <urdf_world/types.h>

namespace mbgen::gen {

urdf::ModelInterfaceSharedPtr parse_urdf_file(const std::string& path);

}  // namespace mbgen::gen
