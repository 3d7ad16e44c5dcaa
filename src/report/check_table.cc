// The check tables of verify, audit, crosscheck and a rehearsal (include/plumb/check_table.h).

#include "plumb/check_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "core/strings.h"
#include "plumb/model.h"

namespace plumb {
using internal::Echo;
using internal::Join;
using internal::Plural;

namespace {

constexpr std::size_t kWidth = 94;
const char* const kIndent = "      ";

// One row for the `members` (indices into `rows`, two or more) that make the same finding: the
// first row's status and check, how many elements and their names, then the first row's
// text as the example.
std::string GroupText(const std::vector<CheckRow>& rows, const std::vector<std::string>& texts,
                      const std::vector<std::size_t>& members) {
  const CheckRow& first = rows[members.front()];
  std::string label = ElementLabel(first.element);
  std::vector<std::string> names;
  for (std::size_t i : members) {
    names.push_back(rows[i].element.name.empty() ? ElementLabel(rows[i].element)
                                                 : rows[i].element.name);
  }
  // the first line without its element, then the count and the names
  const std::string& own = texts[members.front()];
  std::size_t end = own.find('\n');
  std::string head = own.substr(0, end), body = own.substr(end + 1);
  if (head.size() >= label.size() &&
      head.compare(head.size() - label.size(), std::string::npos, label) == 0) {
    head.erase(head.size() - label.size());
  } else {
    head += " ";
  }
  std::string text =
      fmt::format("{}{} {} alike:\n", head, members.size(), Plural(first.element.kind)) +
      Wrap(Join(names, ", "), kWidth, kIndent);
  // the example: the first row's text, named
  std::size_t start = body.find_first_not_of(' ');
  if (start == std::string::npos) return text + kIndent + "e.g. " + label + "\n";
  return text + kIndent + "e.g. " + label + ": " + body.substr(start);
}

// What the SKIPs of one reason (indices into `rows`) are about: each check id once, with the
// elements (or subjects) it skipped: "actuator.stability: rh_A_FFJ0, rh_A_MFJ0; energy", or
// "analytic.period, energy" when none is about an element.
std::string SkippedList(const std::vector<CheckRow>& rows,
                        const std::vector<std::size_t>& members) {
  std::vector<std::string> ids;
  std::map<std::string, std::vector<std::string>> about;  // each id's elements, in order
  bool named = false;
  for (std::size_t i : members) {
    const CheckRow& row = rows[i];
    if (std::find(ids.begin(), ids.end(), row.id) == ids.end()) ids.push_back(row.id);
    std::string what = row.element.name.empty() ? row.About() : row.element.name;
    if (what.empty()) continue;
    about[row.id].push_back(what);
    named = true;
  }
  std::vector<std::string> parts;
  for (const std::string& id : ids) {
    auto it = about.find(id);
    parts.push_back(it == about.end() ? id : id + ": " + Join(it->second, ", "));
  }
  return Join(parts, named ? "; " : ", ");
}

// A row's first line up to its element: the status and the check id in a column `width` wide;
// an accepted row says ACCEPT, its own status following on the line AcceptedLine adds.
std::string Head(const CheckRow& row, int width) {
  if (!row.accepted.empty()) return fmt::format("ACCEPT  {:<{}}", row.id, width - 2);
  return fmt::format("{}  {:<{}}", CheckStatusName(row.status), row.id, width);
}

// "WARN accepted: REASON", wrapped; "" for a row that is not accepted.
std::string AcceptedLine(const CheckRow& row) {
  if (row.accepted.empty()) return "";
  return Wrap(fmt::format("{} accepted: {}", CheckStatusName(row.status), row.accepted), kWidth,
              kIndent);
}

}  // namespace

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
                       const std::vector<std::string>& texts, TableDetail detail,
                       const std::string& how_to_see_all) {
  std::map<CheckStatus, long> count;
  // the SKIPs of each reason: the rows, the first of which shows them all
  std::map<std::string, std::vector<std::size_t>> skipped;
  // the FAIL and WARN rows of each finding made about several elements
  using Finding = std::tuple<std::string, std::string, CheckStatus, std::string, std::string>;
  std::map<Finding, std::vector<std::size_t>> alike;
  std::vector<Finding> finding_of(rows.size());
  long accepted = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CheckRow& row = rows[i];
    // an accepted row counts apart, and shows on its own with its reason
    if (!row.accepted.empty()) {
      ++accepted;
      continue;
    }
    ++count[row.status];
    if ((row.status == CheckStatus::kFail || row.status == CheckStatus::kWarn) &&
        !row.element.empty()) {
      finding_of[i] = {row.section, row.id, row.status, row.finding, row.element.kind};
      alike[finding_of[i]].push_back(i);
    }
    if (row.status != CheckStatus::kSkip) continue;
    skipped[row.explanation].push_back(i);
  }
  std::string counts =
      fmt::format("{} passed, {} warned, {} failed, {} skipped", count[CheckStatus::kPass],
                  count[CheckStatus::kWarn], count[CheckStatus::kFail], count[CheckStatus::kSkip]);
  if (accepted > 0) counts += fmt::format(", {} accepted", accepted);
  if (detail == TableDetail::kQuiet) return counts + "\n";

  std::string out = title + "\n";
  std::string section = "\n";  // no section yet; a blank line after the title
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CheckRow& row = rows[i];
    // by default PASS rows are counted, and SKIPs sharing a reason show as one row
    std::string text = texts[i];
    if (detail == TableDetail::kFindings) {
      if (row.status == CheckStatus::kPass) continue;
      if (row.status == CheckStatus::kSkip) {
        const std::vector<std::size_t>& members = skipped[row.explanation];
        if (members.size() > 1 && members.front() != i) continue;  // shown with the first
        if (members.size() > 1) {
          text = fmt::format("SKIP  {} checks skipped: {}\n", members.size(), row.explanation) +
                 Wrap(SkippedList(rows, members), kWidth, kIndent);
        }
      }
      auto group = alike.find(finding_of[i]);
      if (group != alike.end() && group->second.size() > 1) {
        if (group->second.front() != i) continue;  // shown with the first
        text = GroupText(rows, texts, group->second);
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
    out +=
        " (passed checks not listed" + (how_to_see_all.empty() ? "" : ": " + how_to_see_all) + ")";
  }
  return out + "\n";
}

namespace {

// A row of a measuring check (verify's, crosscheck's): its head and title, what was measured
// against what, its explanation, and the accepted line; with `findings`, also what the row is
// about (its element or subject) and its fix.
std::string MeasuredRowText(const CheckRow& c, int head_width, bool findings) {
  const std::string about = findings ? c.About() : "";
  std::string text = Head(c, head_width) + " " + c.title +
                     (about.empty() ? "" : (c.title.empty() ? "" : ": ") + about) + "\n";
  if (c.status != CheckStatus::kSkip) {
    std::string numbers = "measured " + (c.measured_text.empty() ? "-" : c.measured_text);
    if (!c.reference_text.empty()) numbers += "   reference " + c.reference_text;
    if (std::isfinite(c.rel_error)) numbers += fmt::format("   rel. error {:.2g}", c.rel_error);
    text += Wrap(numbers, kWidth, kIndent);
  }
  text += Wrap(c.explanation, kWidth, kIndent);
  if (findings && !c.fix.empty()) text += Wrap("fix: " + c.fix, kWidth, kIndent);
  return text + AcceptedLine(c);
}

}  // namespace

std::string VerifyTable(const VerifyReport& report, TableDetail detail,
                        const std::string& how_to_see_all) {
  std::vector<std::string> texts;
  for (const CheckRow& c : report.checks) texts.push_back(MeasuredRowText(c, 24, false));
  std::string from = report.start.empty() ? "" : ", from " + report.start;
  std::string table =
      CheckTable(fmt::format("plumb verify {} (MuJoCo {}, tol {:g}{})", report.model,
                             MujocoVersion(), report.tol, from),
                 report.checks, texts, detail, how_to_see_all);
  const VerifyHorizon& h = report.horizon;
  if (!h.shortened()) return table;
  return table + Wrap(fmt::format("Judged on {:g} s of simulated time ({} steps), not {:g} s: {}. "
                                  "An until of {:g} s, given, judges {:g} s.",
                                  h.until, h.steps, h.requested, h.why, h.requested, h.requested),
                      kWidth, "");
}

std::string CrosscheckTable(const CrosscheckReport& report, TableDetail detail,
                            const std::string& how_to_see_all) {
  std::vector<std::string> texts;
  for (const CheckRow& c : report.rows) texts.push_back(MeasuredRowText(c, 28, true));
  const EngineInfo& e = report.engine;
  return CheckTable(fmt::format("plumb crosscheck {} (MuJoCo {}) against {} {} (MuJoCo {}, {} on "
                                "{}; model sent as {})",
                                report.model, report.mujoco_version, e.engine, e.engine_version,
                                e.mujoco_version, e.precision, e.device,
                                report.model_transfer.empty() ? "-" : report.model_transfer),
                    report.rows, texts, detail, how_to_see_all);
}

std::string AuditTable(const AuditReport& report, TableDetail detail,
                       const std::string& how_to_see_all) {
  std::vector<std::string> texts;
  for (const CheckRow& f : report.findings) {
    std::string about = f.About();
    std::string text = Head(f, 26) + " " + (about.empty() ? "(model)" : about) + "\n";
    std::string numbers = kIndent + f.measured_text;
    if (!f.reference_text.empty()) numbers += "   threshold " + f.reference_text;
    text += numbers + "\n";
    // a SKIP's reason shows where a finding's fix does, an accepted finding's reason in its place
    const std::string& fix = f.status == CheckStatus::kSkip ? f.explanation : f.fix;
    if (!f.accepted.empty()) {
      text += AcceptedLine(f);
    } else if (!fix.empty()) {
      text += kIndent + ("fix: " + fix) + "\n";
    }
    texts.push_back(text);
  }
  std::string from = report.start.empty() ? "" : ", from " + report.start;
  return CheckTable(fmt::format("plumb audit {} (MuJoCo {}{})", report.model, MujocoVersion(), from),
                    report.findings, texts, detail, how_to_see_all);
}

namespace {

// "1 assertion holds", "3 assertions hold", "1 of 3 assertions broken", "no assertions".
std::string AssertionsClause(const std::vector<CheckRow>& rows) {
  long total = 0, broken = 0;
  for (const CheckRow& row : rows) {
    if (row.section != "assert") continue;
    ++total;
    if (row.status == CheckStatus::kFail && row.accepted.empty()) ++broken;
  }
  if (total == 0) return "no assertions";
  if (broken > 0) {
    return fmt::format("{} of {} assertion{} broken", broken, total, total == 1 ? "" : "s");
  }
  return total == 1 ? "1 assertion holds" : fmt::format("{} assertions hold", total);
}

}  // namespace

std::string DescribeClientEnding(const ClientEnding& c) {
  std::string name = ClientEndingName(c.kind);
  std::string text = c.text.empty()               ? name
                     : c.text.rfind(name, 0) == 0 ? c.text
                                                  : name + ": " + c.text;
  if (std::isfinite(c.time)) text += fmt::format(" at t = {:.2f} s", c.time);
  if (std::isfinite(c.wall)) text += fmt::format(" ({:.1f} s of wall time)", c.wall);
  return text;
}

std::string RehearsalVerdict(const RehearsalResult& r) {
  std::vector<std::string> parts = {AssertionsClause(r.rows)};
  std::vector<std::string> failed;
  long warned = 0;
  bool diverged_row = false;
  for (const CheckRow& row : r.rows) {
    if (!row.accepted.empty()) continue;
    if (row.status == CheckStatus::kWarn) ++warned;
    if (row.status != CheckStatus::kFail) continue;
    diverged_row = diverged_row || row.id == "bridge.diverged";
    if (row.section != "assert" &&
        std::find(failed.begin(), failed.end(), row.id) == failed.end()) {
      failed.push_back(row.id);
    }
  }
  if (!failed.empty()) parts.push_back(Join(failed, ", ") + " failed");
  if (r.bridge.diverged && !diverged_row) parts.push_back("the simulation diverged");
  if (warned > 0) parts.push_back(fmt::format("{} warning{}", warned, warned == 1 ? "" : "s"));
  parts.push_back("client " + DescribeClientEnding(r.client));
  return fmt::format("rehearsal {}: {}", r.passed() ? "PASS" : "FAIL", Join(parts, "; "));
}

std::string RehearsalTable(const std::string& model, const RehearsalResult& r, TableDetail detail,
                           const std::string& how_to_see_all) {
  const std::vector<CheckRow>& rows = r.rows;  // assert, client, bridge (plumb/rehearse.h)
  std::vector<std::string> texts;
  for (const CheckRow& c : rows) texts.push_back(MeasuredRowText(c, 24, true));
  std::string table = CheckTable(fmt::format("rehearsal of {} over {:g} s simulated (MuJoCo {})",
                                             model, r.bridge.time, MujocoVersion()),
                                 rows, texts, detail, how_to_see_all);
  std::string verdict = RehearsalVerdict(r) + "\n";
  if (detail == TableDetail::kQuiet) return table + verdict;
  const ClientEnding& c = r.client;
  bool lines = !c.last_lines.empty() && (detail == TableDetail::kAll ||
                                         c.kind != ClientEnding::Kind::kStopped || !r.passed());
  table += "\nclient: " + DescribeClientEnding(c) + (lines ? "; its last lines:\n" : "\n");
  if (lines) {
    for (const std::string& line : c.last_lines) table += kIndent + Echo(line, 200) + "\n";
  }
  return table + verdict;
}

}  // namespace plumb
