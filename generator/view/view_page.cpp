#include "view/view_page.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "codegen/output_files.hpp"
#include "load/load_error.hpp"
#include "view/base64.hpp"

namespace mbgen::view {

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw gen::LoadError(path.string(), 0, "a file of mbgen's viewer", "is missing",
                         "rebuild mbgen with npm available (the build installs three.js with npm ci), or reinstall it");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Replaces the one `@@name@@` of `page` by `value`.
void fill(std::string& page, const std::string& name, const std::string& value) {
  const std::string key = "@@" + name + "@@";
  const std::size_t at = page.find(key);
  if (at == std::string::npos) throw std::logic_error(fmt::format("the viewer's page has no {}", key));
  page.replace(at, key.size(), value);
}

}  // namespace

std::string installed_viewer_directory() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  const fs::path directory = (executable.parent_path() / "../share/mbgen/viewer").lexically_normal();
  if (error || !fs::is_regular_file(directory / "three.module.min.js"))
    throw gen::LoadError(directory.string(), 0, "mbgen's viewer (three.js)", "is not installed beside the mbgen executable",
                         "build mbgen with npm available (scripts/install_deps.sh installs it; the build runs npm ci in web/viewer), "
                         "or reinstall it (cmake --install)");
  return directory.string();
}

ViewerAssets read_viewer_assets(const std::string& directory) {
  const fs::path d(directory);
  return {read_text(d / "page.html"), read_text(d / "viewer.js"), read_text(d / "three.module.min.js"),
          read_text(d / "OrbitControls.js")};
}

std::string view_page(const nlohmann::json& scene, const ViewerAssets& assets) {
  std::string json = scene.dump();
  // "</" would end the <script> element that holds the JSON: "<\/" is the same JSON string.
  for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3)) json.replace(at, 2, "<\\/");
  std::string page = assets.page;
  // From the page's end to its start: a value filled in (a robot's name, say) cannot be taken for
  // a placeholder, since each is searched for before it.
  fill(page, "VIEWER", assets.viewer);
  fill(page, "SCENE", json);
  fill(page, "ORBIT_CONTROLS", base64(assets.orbit_controls));
  fill(page, "THREE", base64(assets.three));
  std::string title;
  for (char c : scene.value("robot", std::string("robot"))) title += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  fill(page, "TITLE", title + " — mbgen view");
  return page;
}

void write_view_page(const std::string& path, const std::string& text) {
  if (fs::exists(path)) {
    std::ifstream in(path, std::ios::binary);
    std::string head(4096, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    if (head.find(kViewPageMark) == std::string::npos)
      throw codegen::OutputRefused(fmt::format("{}: error: the file exists and was not written by mbgen view (no `{}` near its top)\n"
                                               "  fix: choose another --out, or move the file away; mbgen never overwrites files it "
                                               "did not write", path, kViewPageMark));
  }
  codegen::write_via_temporary(path, text);
}

}  // namespace mbgen::view
