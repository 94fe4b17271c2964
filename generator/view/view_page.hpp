#pragma once
// A page of `mbgen view`: web/viewer/page.html with three.js, its orbit controls, the scene JSON
// and web/viewer/viewer.js inlined, so that the one HTML file opens from disk with no server and
// no network. The assets are found beside the mbgen executable (share/mbgen/viewer, copied there
// by the build from npm's three.js, its licence kept beside it).
#include <string>

#include <nlohmann/json.hpp>

namespace mbgen::view {

/// The files a page is made of.
struct ViewerAssets {
  std::string page, viewer, three, orbit_controls;
};

/// The folder share/mbgen/viewer beside the running executable. Throws gen::LoadError if the
/// build did not install three.js there.
std::string installed_viewer_directory();

/// Reads page.html, viewer.js, three.module.min.js and OrbitControls.js from `directory`.
/// Throws gen::LoadError naming a missing file.
ViewerAssets read_viewer_assets(const std::string& directory);

/// The page's text. The JSON is escaped for a <script> element (no "</" inside).
std::string view_page(const nlohmann::json& scene, const ViewerAssets& assets);

/// What the first lines of every page carry: mbgen view overwrites only files that do.
inline constexpr const char* kViewPageMark = "<meta name=\"generator\" content=\"mbgen view\">";

/// Writes `text` to `path` unless a file is there that mbgen view did not write (then throws
/// codegen::OutputRefused).
void write_view_page(const std::string& path, const std::string& text);

}  // namespace mbgen::view
