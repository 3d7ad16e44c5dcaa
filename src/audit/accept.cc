// Accept lists: reading one from TOML with toml++ (every error names file:line:column), and
// applying it to check rows (include/plumb/accept.h).

#include "plumb/accept.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>

#include "core/input_file.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb {
using internal::Closest;
using internal::InputKind;
using internal::Join;
using internal::Nearest;
using internal::ReadInputFile;
using internal::Trim;

namespace {

// The keys an [[accept]] table reads.
const std::vector<std::string>& EntryKeys() {
  static const std::vector<std::string> keys = {"check", "element", "status", "reason"};
  return keys;
}

[[noreturn]] void Bad(const std::string& file, const toml::source_region& where,
                      const std::string& problem) {
  throw ValueError(
      fmt::format("{}:{}:{}: {}", file, where.begin.line, where.begin.column, problem));
}

// "; did you mean: X?" for a plausible typo of one of `known`, else "".
std::string Guess(const std::string& word, const std::vector<std::string>& known) {
  std::vector<std::string> close = Closest(word, known);
  return close.empty() ? "" : "; did you mean: " + Join(close, ", ") + "?";
}

// `text` without every " (id N)" in it.
std::string WithoutIds(std::string text) {
  const std::string open = " (id ";
  std::size_t at = text.find(open);
  while (at != std::string::npos) {
    std::size_t end = at + open.size();
    while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
    bool id = end > at + open.size() && end < text.size() && text[end] == ')';
    if (id) text.erase(at, end + 1 - at);
    at = text.find(open, id ? at : at + 1);
  }
  return text;
}

// A string entry of an [[accept]] table, or nullopt when it is not there.
std::optional<std::string> Text(const std::string& file, const toml::table& entry,
                                const std::string& key, const char* what) {
  const toml::node* node = entry.get(key);
  if (node == nullptr) return std::nullopt;
  std::optional<std::string> text = node->value_exact<std::string>();
  if (!text) Bad(file, node->source(), fmt::format("'{}' must be a string: {}", key, what));
  return std::string(Trim(*text));
}

AcceptEntry ReadEntry(const std::string& file, const toml::table& t) {
  for (const auto& [key, node] : t) {
    std::string name(key.str());
    const std::vector<std::string>& keys = EntryKeys();
    if (std::find(keys.begin(), keys.end(), name) != keys.end()) continue;
    Bad(file, key.source(),
        fmt::format("an [[accept]] entry has no key '{}'; it reads {}{}", name, Join(keys, ", "),
                    Guess(name, keys)));
  }
  AcceptEntry entry;
  entry.line = static_cast<int>(t.source().begin.line);
  std::optional<std::string> check = Text(file, t, "check", "the id of the row to accept");
  if (!check || check->empty()) {
    Bad(file, check ? t.get("check")->source() : t.source(),
        "an [[accept]] entry needs 'check', the id of the row it accepts (\"inertia.shape\")");
  }
  entry.check = *check;
  entry.element =
      Text(file, t, "element", "what the row is about, as \"body 'base_link'\"").value_or("");
  if (entry.element != WithoutIds(entry.element)) {
    Bad(file, t.get("element")->source(),
        fmt::format("element \"{}\" names an id; name the element without it (\"{}\"): ids shift "
                    "as the model changes",
                    entry.element, WithoutIds(entry.element)));
  }
  if (std::optional<std::string> status = Text(file, t, "status", "\"WARN\" or \"FAIL\"")) {
    if (*status != "WARN" && *status != "FAIL") {
      Bad(file, t.get("status")->source(),
          fmt::format("status \"{}\" is not \"WARN\" or \"FAIL\" (only those rows are accepted; "
                      "leave it out to accept either)",
                      *status));
    }
    entry.status = *status == "WARN" ? CheckStatus::kWarn : CheckStatus::kFail;
  }
  std::optional<std::string> reason = Text(file, t, "reason", "why the finding is acceptable");
  if (!reason || reason->empty()) {
    Bad(file, reason ? t.get("reason")->source() : t.source(),
        fmt::format("the [[accept]] entry for {} needs a 'reason': why the finding is "
                    "acceptable, who judged it and when",
                    entry.check));
  }
  entry.reason = *reason;
  return entry;
}

// "inertia.shape about body 'base_link'", "structure.counts about the model", and " (WARN only)"
// when the entry has a status.
std::string Named(const AcceptEntry& e) {
  std::string text = e.check + " about " + (e.element.empty() ? "the model" : e.element);
  if (e.status) text += fmt::format(" ({} only)", CheckStatusName(*e.status));
  return text;
}

bool Finding(const CheckRow& row) {
  return row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail;
}

bool Unnamed(const CheckRow& row) { return !row.element.empty() && row.element.name.empty(); }

// The row a stale entry becomes: what it named, what became of it, what to do.
CheckRow StaleRow(const AcceptList& list, const AcceptEntry& e, const std::vector<CheckRow>& rows) {
  std::string where = list.file.empty() ? fmt::format("entry {}", &e - list.entries.data() + 1)
                                        : fmt::format("{}:{}", list.file, e.line);
  CheckRow row;
  row.status = CheckStatus::kWarn;
  row.id = kAcceptStale;
  row.section = "accept";
  row.title = "an accepted finding that is no longer there";
  row.subject = where + ": " + Named(e);
  row.explanation = "accepted because: " + e.reason;
  // the same check about the same element in another state (a WARN or FAIL before the rest)
  const CheckRow* same = nullptr;
  for (const CheckRow& r : rows) {
    if (r.id != e.check || AcceptElement(r) != e.element) continue;
    if (same == nullptr || (Finding(r) && !Finding(*same))) same = &r;
  }
  if (same != nullptr && Unnamed(*same)) {
    row.measured_text = e.element + " has no name";
    row.fix =
        "an unnamed element cannot be accepted (its id shifts as the model changes): "
        "name it in the model, then accept it by name";
    return row;
  }
  if (same != nullptr && !Finding(*same)) {
    row.measured_text = fmt::format("now {}", CheckStatusName(same->status));
    row.fix = "the finding it accepted is gone: delete the entry (" + where + ")";
    return row;
  }
  if (same != nullptr) {  // a finding of another status than the entry's
    row.measured_text = fmt::format("now {}; the entry accepts a {} only",
                                    CheckStatusName(same->status), CheckStatusName(*e.status));
    row.fix = fmt::format("judge the {} anew: fix the model, or change the entry's status",
                          CheckStatusName(same->status));
    return row;
  }
  // else: what rows there are, for a misspelt or renamed check or element
  std::vector<std::string> ids, elements;
  for (const CheckRow& r : rows) {
    if (std::find(ids.begin(), ids.end(), r.id) == ids.end()) ids.push_back(r.id);
    std::string element = AcceptElement(r);
    if (r.id == e.check && Finding(r) && !Unnamed(r) &&
        std::find(elements.begin(), elements.end(), element) == elements.end()) {
      elements.push_back(element);
    }
  }
  bool checked = std::find(ids.begin(), ids.end(), e.check) != ids.end();
  if (!checked) {
    row.measured_text = "no WARN or FAIL of " + e.check;
    row.fix = fmt::format("delete the entry ({}) if its finding is gone, or correct its check{}",
                          where, Guess(e.check, ids));
  } else {
    row.measured_text = fmt::format("no WARN or FAIL of {} about {}", e.check,
                                    e.element.empty() ? "the model" : e.element);
    row.fix = fmt::format(
        "delete the entry ({}) if its finding is gone, or name the element as the rows do, by "
        "kind and name (\"body 'name'\")",
        where);
    if (!elements.empty()) {
      row.fix +=
          fmt::format("; {} is about: {}", e.check, Join(Nearest(e.element, elements), ", "));
    }
  }
  return row;
}

}  // namespace

AcceptList LoadAcceptList(const std::string& path) {
  std::string text = ReadInputFile(path, InputKind::kAcceptList);
  toml::table table;
  try {
    table = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    Bad(path, e.source(), "not valid TOML: " + std::string(e.description()));
  }
  AcceptList list;
  list.file = path;
  for (const auto& [key, node] : table) {
    if (key.str() == "accept") continue;
    Bad(path, key.source(),
        fmt::format("unknown key '{}': an accept list holds [[accept]] tables only", key.str()));
  }
  const toml::node* accept = table.get("accept");
  if (accept == nullptr) return list;
  const toml::array* entries = accept->as_array();
  if (entries == nullptr || (!entries->empty() && !entries->is_array_of_tables())) {
    Bad(path, accept->source(),
        "'accept' must be [[accept]] tables, each with check, element, reason (and status)");
  }
  for (const toml::node& node : *entries) {
    AcceptEntry entry = ReadEntry(path, *node.as_table());
    for (const AcceptEntry& before : list.entries) {
      if (before.check == entry.check && before.element == entry.element &&
          before.status == entry.status) {
        Bad(path, node.source(),
            fmt::format("this entry repeats the one at line {} ({})", before.line, Named(before)));
      }
    }
    list.entries.push_back(std::move(entry));
  }
  return list;
}

std::string AcceptElement(const CheckRow& row) {
  if (row.element.empty()) return WithoutIds(row.subject);
  if (row.element.name.empty()) return ElementLabel(row.element);  // "body #3"
  return row.element.kind + " '" + row.element.name + "'";
}

bool Accepts(const AcceptEntry& entry, const CheckRow& row) {
  return Finding(row) && !Unnamed(row) && row.id == entry.check &&
         (!entry.status || *entry.status == row.status) && AcceptElement(row) == entry.element;
}

void ApplyAcceptList(const AcceptList& list, std::vector<CheckRow>* rows) {
  std::vector<CheckRow> stale;
  for (const AcceptEntry& entry : list.entries) {
    bool used = false;
    for (CheckRow& row : *rows) {
      if (!Accepts(entry, row)) continue;
      used = true;
      if (row.accepted.empty()) row.accepted = entry.reason;
    }
    if (!used) stale.push_back(StaleRow(list, entry, *rows));
  }
  rows->insert(rows->end(), stale.begin(), stale.end());
}

}  // namespace plumb
