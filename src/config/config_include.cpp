// `include = ["modes.toml", "coefficients.toml"]` at the top of a config:
// the tables of the named files merged into the including one, so that the
// fragments `chatter fit --out` and `chatter coefficients --out` write are
// used as they are (docs/config.md, "Several files").
//
// Rules: the names are relative to the directory of the file that names
// them; an included file may include others (at most kMaxIncludeDepth deep,
// kMaxIncludedFiles in all); a file that includes itself, directly or
// through others, is refused with the chain; a key given in two files
// (a value, or an array) is refused with both files named — tables
// ([process], [tool]) merge key by key, and mode lists (tool.modes,
// workpiece.modes) append: one fragment per tap test. Messages about a key
// name the file it is in (Document::add_source).
#include <cstdint>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "config_sections.hpp"

namespace chatter::config_detail {
namespace {

constexpr int kMaxIncludeDepth = 8;
constexpr std::size_t kMaxIncludedFiles = 32;
constexpr std::uintmax_t kMaxIncludedBytes = 16u << 20;  // 16 MiB, far above any config

struct Merger {
  const ParseFile& parse;
  std::vector<IncludedFile> files;
  std::vector<std::string> clashes;
  std::string root_origin;

  // The file that gave `path` so far: an included file, else the root.
  std::string owner(const Path& path) const {
    for (const IncludedFile& f : files)
      for (const Path& p : f.paths)
        if (path_under(path, p)) return f.origin;
    return root_origin;
  }

  // Moves the keys of `from` (read from files[index]) into `into`.
  void merge(toml::table& into, toml::table& from, const Path& at, std::size_t index) {
    for (auto&& [key, value] : from) {
      const Path path = child(at, key.str());
      toml::node* existing = into.get(key.str());
      if (!existing) {
        into.insert(key, std::move(value));
        files[index].paths.push_back(path);
        continue;
      }
      toml::table* a = existing->as_table();
      toml::table* b = value.as_table();
      if (a && b && !a->is_inline() && !b->is_inline()) {
        merge(*a, *b, path, index);
        continue;
      }
      // Mode lists append: two tap tests (x and y), each fitted to its own
      // fragment, make one body (issue 44). Each appended mode is this
      // file's (Document::origin_of takes the longest matching path).
      toml::array* list = existing->as_array();
      toml::array* more = value.as_array();
      if (key.str() == "modes" && list && more && list->is_array_of_tables() && more->is_array_of_tables()) {
        for (auto&& mode : *more) {
          files[index].paths.push_back(path + "[" + std::to_string(list->size()) + "]");
          list->push_back(std::move(*mode.as_table()));
        }
        continue;
      }
      clashes.push_back(files[index].origin + ": " + path + ": also given in " + owner(path) +
                        " (a key is given in one file only)");
    }
  }

  // The files `root` (read from `origin`) names in `include`, merged into it
  // (theirs first); `chain`: the files being included, outermost first.
  void include(toml::table& root, const std::filesystem::path& origin, std::vector<std::filesystem::path> chain) {
    const toml::node* list = root.get("include");
    if (!list) return;
    const std::string where = origin.string() + ": include";
    const toml::array* names = list->as_array();
    if (!names) throw InputError(where + ": must be an array of file names (include = [\"modes.toml\"])");
    std::vector<std::string> given;
    for (std::size_t i = 0; i < names->size(); ++i) {
      const auto name = names->get(i)->value<std::string>();
      if (!name || name->empty())
        throw InputError(where + "[" + std::to_string(i) + "]: must be a file name (a non-empty string)");
      given.push_back(*name);
    }
    root.erase("include");
    if (static_cast<int>(chain.size()) > kMaxIncludeDepth)
      throw InputError(where + ": more than " + std::to_string(kMaxIncludeDepth) + " levels of include");
    for (std::size_t i = 0; i < given.size(); ++i) {
      const std::string at = where + "[" + std::to_string(i) + "] = \"" + given[i] + "\"";
      std::filesystem::path file(given[i]);
      if (file.is_relative()) file = origin.parent_path() / file;
      std::error_code ec;
      const std::filesystem::path id = std::filesystem::weakly_canonical(file, ec);
      for (const std::filesystem::path& c : chain)
        if (!ec && c == id) {
          std::string cycle;
          for (const std::filesystem::path& d : chain) cycle += d.string() + " -> ";
          throw InputError(at + ": includes a file being included (a cycle: " + cycle + id.string() + ")");
        }
      if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(at + ": " + file.string() + ": cannot read file (" +
                         (std::filesystem::exists(file, ec) ? "not a regular file" : "no such file") + ")");
      if (std::filesystem::file_size(file, ec) > kMaxIncludedBytes)
        throw InputError(at + ": " + file.string() + ": larger than 16 MiB, not a config");
      if (files.size() >= kMaxIncludedFiles)
        throw InputError(at + ": more than " + std::to_string(kMaxIncludedFiles) + " included files");
      IncludedFile f;
      f.origin = file.string();
      toml::table included;
      try {
        included = parse(file, &f.text);
      } catch (const InputError& e) {
        throw InputError(at + ": " + e.what());
      }
      std::vector<std::filesystem::path> inner = chain;
      inner.push_back(ec ? file : id);
      include(included, file, inner);
      files.push_back(std::move(f));
      merge(root, included, "", files.size() - 1);
    }
  }
};

}  // namespace

std::vector<IncludedFile> merge_includes(toml::table& root, const std::string& origin, const ParseFile& parse) {
  Merger m{parse, {}, {}, origin};
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::weakly_canonical(origin, ec);
  m.include(root, origin, {ec ? std::filesystem::path(origin) : self});
  if (!m.clashes.empty()) {
    std::string message;
    for (const std::string& c : m.clashes) message += (message.empty() ? "" : "\n") + c;
    throw InputError(message);
  }
  return std::move(m.files);
}

}  // namespace chatter::config_detail
