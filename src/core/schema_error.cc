// Where a schema violation is and what was meant (core/schema_error.h).

#include "core/schema_error.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>

#include "core/strings.h"

namespace plumb::internal {
namespace {

namespace fs = std::filesystem;

// MuJoCo's schema, element by element: every attribute of every place the element stands.
std::map<std::string, std::set<std::string>> ReadSchema() {
  std::vector<char> buffer(1 << 18, 0);
  mj_printSchema(nullptr, buffer.data(), static_cast<int>(buffer.size()), 0, 0);
  std::map<std::string, std::set<std::string>> schema;
  std::istringstream lines(std::string(buffer.data()));
  std::string line, element;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    std::size_t first = 0;
    // "   geom (*)   adhesion axisangle ...": an element, then its attributes; a line that
    // starts with an attribute goes on with the element above
    if (tokens.size() >= 2 && tokens[1].front() == '(' && tokens[1].back() == ')') {
      element = tokens[0];
      first = 2;
      schema[element];
    }
    if (element.empty()) continue;
    for (std::size_t k = first; k < tokens.size(); ++k) schema[element].insert(tokens[k]);
  }
  return schema;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` with its XML comments blanked (newlines kept, so lines still count).
std::string WithoutComments(std::string text) {
  for (std::size_t at = text.find("<!--"); at != std::string::npos; at = text.find("<!--", at)) {
    std::size_t end = text.find("-->", at + 4);
    end = end == std::string::npos ? text.size() : end + 3;
    for (std::size_t k = at; k < end; ++k) {
      if (text[k] != '\n') text[k] = ' ';
    }
    at = end;
  }
  return text;
}

bool IsSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// The 1-based line of the first <element ... attribute=...> in `text`; 0 when none.
int AttributeLine(const std::string& text, const std::string& element,
                  const std::string& attribute) {
  const std::string open = "<" + element;
  for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at + 1)) {
    std::size_t after = at + open.size();
    if (after >= text.size() || !(IsSpace(text[after]) || text[after] == '/')) continue;
    std::size_t end = text.find('>', after);
    if (end == std::string::npos) end = text.size();
    // within the tag only: a search past its end would make a large file quadratic
    const std::string_view tag = std::string_view(text).substr(0, end);
    for (std::size_t k = tag.find(attribute, after); k != std::string_view::npos;
         k = tag.find(attribute, k + 1)) {
      std::size_t next = k + attribute.size();
      while (next < end && IsSpace(text[next])) ++next;
      if (IsSpace(text[k - 1]) && next < end && text[next] == '=') {
        return 1 + static_cast<int>(std::count(text.begin(), text.begin() + k, '\n'));
      }
    }
    at = end;
  }
  return 0;
}

// The file= of every <include> in `text`.
std::vector<std::string> Includes(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t at = text.find("<include"); at != std::string::npos;
       at = text.find("<include", at + 1)) {
    std::size_t end = text.find('>', at);
    if (end == std::string::npos) break;
    const std::string_view tag = std::string_view(text).substr(0, end);  // this tag only
    std::size_t file = tag.find("file", at);
    if (file == std::string::npos) continue;
    std::size_t quote = tag.find_first_of("\"'", file);
    if (quote == std::string::npos) continue;
    std::size_t close = tag.find(text[quote], quote + 1);
    if (close == std::string::npos) continue;
    out.push_back(text.substr(quote + 1, close - quote - 1));
  }
  return out;
}

struct Place {
  fs::path file;
  std::string included_by;  // "" for the model's own file
  int line = 0;
};

// Depth first through `file` and what it includes (MuJoCo resolves an include against the
// model's folder; the including file's folder is tried too).
bool Find(const fs::path& file, const fs::path& top_dir, const std::string& element,
          const std::string& attribute, const std::string& included_by,
          std::set<fs::path>* seen, Place* place) {
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(file, ec);
  if (ec || !seen->insert(canonical).second || seen->size() > 64) return false;
  const std::string text = WithoutComments(ReadText(file));
  if (int line = AttributeLine(text, element, attribute); line > 0) {
    *place = {file, included_by, line};
    return true;
  }
  for (const std::string& name : Includes(text)) {
    for (const fs::path& dir : {top_dir, file.parent_path()}) {
      fs::path candidate =
          fs::path(name).is_absolute() || dir == "." ? fs::path(name) : dir / name;
      if (!fs::is_regular_file(candidate, ec)) continue;
      if (Find(candidate, top_dir, element, attribute, file.string(), seen, place)) return true;
      break;
    }
  }
  return false;
}

// The text between `before` and the next `after` in `text`; "" when absent.
std::string Between(const std::string& text, const std::string& before, char after) {
  std::size_t at = text.find(before);
  if (at == std::string::npos) return "";
  at += before.size();
  std::size_t end = text.find(after, at);
  return end == std::string::npos ? "" : text.substr(at, end - at);
}

}  // namespace

std::vector<std::string> SchemaAttributes(const std::string& element) {
  static const std::map<std::string, std::set<std::string>> schema = ReadSchema();
  auto it = schema.find(element);
  if (it == schema.end()) return {};
  return {it->second.begin(), it->second.end()};
}

std::string SchemaErrorPlace(const std::string& error, const std::string& path) {
  const std::string attribute = Between(error, "unrecognized attribute: '", '\'');
  const std::string element = Between(error, "Element '", '\'');
  if (attribute.empty() || element.empty()) return "";
  Place place;
  std::set<fs::path> seen;
  fs::path top(path);
  fs::path top_dir = top.parent_path().empty() ? fs::path(".") : top.parent_path();
  std::string where;
  if (Find(top, top_dir, element, attribute, "", &seen, &place)) {
    where = "'" + attribute + "' stands on line " + std::to_string(place.line) + " of '" +
            place.file.string() + "'" +
            (place.included_by.empty() ? "" : " (included by '" + place.included_by + "')");
  }
  const std::vector<std::string> close = Closest(attribute, SchemaAttributes(element));
  std::string near = close.empty() ? "" : "did you mean: " + Join(close, ", ") + "?";
  if (where.empty() && near.empty()) return "";
  if (where.empty()) return "<" + element + "> takes no '" + attribute + "': " + near;
  return where + (near.empty() ? "" : "; " + near);
}

}  // namespace plumb::internal
