#pragma once
// The skeletons of the emitted files (templates/<flavour>/*.fmt, docs/templates.md): text with
// named fmt placeholders ({robot}, {body}, ...; {{ and }} are literal braces). codegen computes
// only what varies (statements, sizes, names, operation counts) and renders the templates with
// it; the shape of the output (banner, includes, namespaces, declarations, entry points) is the
// templates'. A template set is loaded and checked whole before anything is rendered: a missing
// file, an unknown or positional placeholder, or an unmatched brace is a LoadError naming the
// file, the line and the placeholder. As in Jinja, a template file's final newline is not part
// of the template (so every file can end in one); a name template is its first line.
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mbgen::codegen {

/// One placeholder a template may use.
struct PlaceholderSpec {
  const char* name;
  const char* meaning;
};

/// One template every set must have: templates/<flavour>/<name>.fmt.
struct TemplateSpec {
  const char* name;
  const char* purpose;
  std::vector<PlaceholderSpec> placeholders;
  /// A name template (a file name or an identifier): its first line is the value.
  bool single_line = false;
};

/// Every template of a set, with the placeholders each may use (docs/templates.md lists them).
const std::vector<TemplateSpec>& template_catalog();

/// Values for a template's placeholders, by name.
using TemplateFields = std::vector<std::pair<std::string, std::string>>;

class TemplateSet {
 public:
  /// Reads and checks every template of the catalog from `directory`. Throws gen::LoadError
  /// naming the file (and line and placeholder) on: a missing or unreadable file, a
  /// placeholder the template may not use, a positional placeholder ({} or {0}), an unmatched
  /// brace, a banner that does not begin with kBannerFirstLine (mbgen recognises its own files
  /// by it), an empty name template.
  static TemplateSet load(const std::string& directory);
  /// The same for another catalog's templates (the Python module's: emit_python.hpp). The catalog
  /// must outlive the set.
  static TemplateSet load(const std::string& directory, const std::vector<TemplateSpec>& catalog);

  /// The template `name` with its placeholders replaced by `fields`, which give exactly the
  /// placeholders the catalog lists for it (std::logic_error otherwise: a codegen bug); a
  /// template may use any of them. Throws gen::LoadError naming the file if fmt refuses a
  /// format specification ({robot:d}).
  std::string render(const std::string& name, const TemplateFields& fields) const;

  const std::string& directory() const { return directory_; }

  /// SHA-256 over the templates' names and contents, in catalog order: what the banner names
  /// when a user's templates are used.
  std::string digest() const;

 private:
  std::string directory_;
  const std::vector<TemplateSpec>* catalog_ = nullptr;
  std::map<std::string, std::string> text_;  ///< by template name
};

/// The folder of the templates installed with the generator for `flavour` (cpp, c):
/// <directory of the running mbgen>/<MBGEN_TEMPLATES_RELATIVE>/<flavour>. Throws gen::LoadError
/// when there is no such flavour, naming the ones there are.
std::string installed_templates_directory(const std::string& flavour);

}  // namespace mbgen::codegen
