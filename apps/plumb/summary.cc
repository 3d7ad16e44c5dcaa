#include "summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>

#include "plumb/strings.h"

namespace plumb::cli {
namespace {
// "actuator" -> "actuators", "body" -> "bodies"; "elements" for no type.
std::string Plural(const std::string& type) {
  if (type.empty()) return "elements";
  if (type.back() == 'y') return type.substr(0, type.size() - 1) + "ies";
  return type + (type.back() == 's' ? "es" : "s");
}

// One row for the `members` (indices into `rows`, two or more) that make the same finding: the
// first row's status and check, how many elements and their names, then the first row's
// message as the example.
std::string FindingGroupText(const std::vector<CheckRow>& rows,
                             const std::vector<std::size_t>& members) {
  const CheckRow& first = rows[members.front()];
  std::vector<std::string> names;
  for (std::size_t i : members) {
    names.push_back(rows[i].element_name.empty() ? rows[i].element : rows[i].element_name);
  }
  // the first line without its element, then the count and the names
  std::size_t end = first.text.find('\n');
  std::string head = first.text.substr(0, end), body = first.text.substr(end + 1);
  if (head.size() >= first.element.size() &&
      head.compare(head.size() - first.element.size(), std::string::npos, first.element) == 0) {
    head.erase(head.size() - first.element.size());
  } else {
    head += " ";
  }
  std::string text =
      fmt::format("{}{} {} alike:\n", head, members.size(), Plural(first.element_type)) +
      Wrap(Join(names, ", "), 94, "      ");
  // the example: the first row's message, named
  std::size_t start = body.find_first_not_of(' ');
  if (start == std::string::npos) return text + "      e.g. " + first.element + "\n";
  return text + "      e.g. " + first.element + ": " + body.substr(start);
}
}  // namespace

std::string FindingShape(const std::string& text) {
  auto in_word = [&text](std::size_t i) {
    return i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_');
  };
  auto digit = [&text](std::size_t i) {
    return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]));
  };
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    bool word_start = i == 0 || !in_word(i - 1);
    // a quoted name: 'hip' (an apostrophe inside a word, as in motor's, opens nothing)
    if (text[i] == '\'' && word_start) {
      std::size_t close = text.find('\'', i + 1);
      if (close != std::string::npos && !in_word(close + 1)) {
        out += "''";
        i = close + 1;
        continue;
      }
    }
    // a number: sign, digits, fraction, exponent
    bool sign = (text[i] == '-' || text[i] == '+') && digit(i + 1);
    if (word_start && (digit(i) || sign)) {
      std::size_t j = i + (sign ? 1 : 0);
      while (digit(j)) ++j;
      if (j < text.size() && text[j] == '.' && digit(j + 1)) {
        for (++j; digit(j);) ++j;
      }
      if (j < text.size() && (text[j] == 'e' || text[j] == 'E')) {
        std::size_t k = j + 1;
        if (k < text.size() && (text[k] == '-' || text[k] == '+')) ++k;
        if (digit(k)) {
          for (j = k; digit(j);) ++j;
        }
      }
      out += '#';
      i = j;
      continue;
    }
    out += text[i++];
  }
  return out;
}

void AddTableDetailOptions(CLI::App* cmd, TableDetail* detail) {
  CLI::Option* all = cmd->add_flag_callback(
      "--all", [detail] { *detail = TableDetail::kAll; },
      "show every check, PASS rows included (default: failures, warnings and skips)");
  CLI::Option* quiet = cmd->add_flag_callback(
      "--quiet", [detail] { *detail = TableDetail::kQuiet; }, "print the count line alone");
  all->excludes(quiet);
}

std::string Wrap(const std::string& text, std::size_t width, const std::string& indent) {
  std::string out, line;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    std::string word = text.substr(start, end - start);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += indent + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  if (!line.empty()) out += indent + line + "\n";
  return out;
}

std::string CheckTable(const std::string& title, const std::vector<CheckRow>& rows,
                       TableDetail detail) {
  std::map<CheckStatus, long> count;
  // the SKIPs of each reason: their ids and the row that shows them
  std::map<std::string, std::pair<std::size_t, std::vector<std::string>>> skipped;
  // the FAIL and WARN rows of each finding made about several elements, by shape
  std::map<std::string, std::vector<std::size_t>> alike;
  std::vector<std::string> shape(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ++count[rows[i].status];
    bool finding = rows[i].status == CheckStatus::kFail || rows[i].status == CheckStatus::kWarn;
    if (finding && !rows[i].element.empty()) {
      shape[i] = rows[i].section + "\n" + FindingShape(rows[i].text);
      alike[shape[i]].push_back(i);
    }
    if (rows[i].status != CheckStatus::kSkip) continue;
    auto it = skipped.try_emplace(rows[i].skip_reason, i, std::vector<std::string>()).first;
    it->second.second.push_back(rows[i].id);
  }
  std::string counts =
      fmt::format("{} passed, {} warned, {} failed, {} skipped", count[CheckStatus::kPass],
                  count[CheckStatus::kWarn], count[CheckStatus::kFail], count[CheckStatus::kSkip]);
  if (detail == TableDetail::kQuiet) return counts + "\n";

  std::string out = title + "\n";
  std::string section = "\n";  // no section yet; a blank line after the title
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CheckRow& row = rows[i];
    // by default PASS rows are counted, and SKIPs sharing a reason show as one row
    std::string text = row.text;
    if (detail == TableDetail::kFindings) {
      if (row.status == CheckStatus::kPass) continue;
      if (row.status == CheckStatus::kSkip) {
        const auto& [shown_at, ids] = skipped[row.skip_reason];
        if (ids.size() > 1 && shown_at != i) continue;  // shown with the first
        if (ids.size() > 1) {
          text = fmt::format("SKIP  {} checks skipped: {}\n", ids.size(), row.skip_reason) +
                 Wrap(Join(ids, ", "), 94, "      ");
        }
      }
      if (!shape[i].empty() && alike[shape[i]].size() > 1) {
        const std::vector<std::size_t>& members = alike[shape[i]];
        if (members.front() != i) continue;  // shown with the first
        text = FindingGroupText(rows, members);
      }
    }
    if (row.section != section) {
      section = row.section;
      out += section.empty() ? "\n" : "\n== " + section + "\n";
    }
    out += text;
  }
  out += "\n" + counts;
  if (detail == TableDetail::kFindings && count[CheckStatus::kPass] > 0) {
    out += " (passed checks not listed: --all shows every check)";
  }
  return out + "\n";
}

}  // namespace plumb::cli
