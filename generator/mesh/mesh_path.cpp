#include "mesh/mesh_path.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "mesh/read_mesh.hpp"

namespace mbgen::mesh {

namespace fs = std::filesystem;

std::pair<std::string, std::string> parse_package_path(const std::string& value) {
  const auto eq = value.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == value.size())
    throw std::invalid_argument(fmt::format("--package-path '{}': expected NAME=DIR, e.g. example-robot-data=/opt/erd", value));
  return {value.substr(0, eq), value.substr(eq + 1)};
}

std::string resolve_mesh_path(const std::string& reference, const std::string& description_dir, const PackagePaths& packages) {
  const std::string file_scheme = "file://";
  // package:// (ROS) and model:// (SDFormat, Gazebo) both name a folder and a path inside it.
  std::string package_scheme;
  for (const char* scheme : {"package://", "model://"})
    if (reference.rfind(scheme, 0) == 0) package_scheme = scheme;
  if (!package_scheme.empty()) {
    const std::string rest = reference.substr(package_scheme.size());
    const auto slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    if (auto it = packages.find(name); it != packages.end()) return (fs::path(it->second) / inside).string();
    std::string tried;
    if (const char* ros = std::getenv("ROS_PACKAGE_PATH")) {
      std::stringstream folders(ros);
      for (std::string folder; std::getline(folders, folder, ':');) {
        if (folder.empty()) continue;
        const fs::path candidate = fs::path(folder) / name / inside;
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec)) return candidate.string();
        tried += fmt::format(" {}", candidate.string());
      }
    }
    throw MeshError(fmt::format("{}: {} '{}' is unknown{}; give --package-path {}=DIR (DIR holds what follows "
                                "the package name) or add its parent folder to ROS_PACKAGE_PATH",
                                reference, package_scheme == "model://" ? "model" : "package", name, tried.empty() ? "" : fmt::format(" (tried{})", tried), name));
  }
  const std::string path = reference.rfind(file_scheme, 0) == 0 ? reference.substr(file_scheme.size()) : reference;
  if (fs::path(path).is_absolute()) return path;
  return (fs::path(description_dir) / path).string();
}

}  // namespace mbgen::mesh
