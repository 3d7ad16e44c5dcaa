// The check tables of `plumb verify` and `plumb audit`: findings first, the rest counted.

#ifndef PLUMB_APPS_PLUMB_SUMMARY_H_
#define PLUMB_APPS_PLUMB_SUMMARY_H_

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "plumb/verify.h"

namespace plumb::cli {

// How much of a check table to print: the findings (FAIL and WARN rows, SKIPs grouped by
// reason, PASS rows counted), every row (--all), or the count line alone (--quiet).
enum class TableDetail { kFindings, kAll, kQuiet };

// Adds --all and --quiet (mutually exclusive) to `cmd`, setting `*detail`.
void AddTableDetailOptions(CLI::App* cmd, TableDetail* detail);

// One row of a check table. `section` starts a "== section" heading when it changes (audit's
// layers; empty for none); `text` is the row as printed with --all (status first, one or more
// lines each ending in a newline); `id` names the check in a group of SKIPs; `skip_reason` is
// what SKIPs with the same reason are grouped by. A row about one model element names it in
// `element` exactly as the end of its first line shows it ("actuator 'hip' (id 3)"), with its
// `element_type` ("actuator") and `element_name` ("hip", "" when unnamed); rows without an
// element are never grouped.
struct CheckRow {
  CheckStatus status = CheckStatus::kPass;
  std::string section, id, text, skip_reason;
  std::string element, element_type, element_name;
};

// The table: `title` (a line), the rows `detail` asks for, and the count line "N passed, W
// warned, F failed, S skipped", saying how to see rows it left out. kQuiet gives the count
// line alone. By default SKIPs sharing a reason become one row: "SKIP  8 checks skipped:
// REASON" with their ids below; and FAIL or WARN rows that make the same finding about several
// elements (the same section and the same text once quoted names and numbers are set aside,
// see FindingShape) become one row: "WARN  actuator.limits  12 actuators alike: NAMES", then
// the first row's message as the example ("e.g. actuator 'hip' (id 0): ...") and its fix.
std::string CheckTable(const std::string& title, const std::vector<CheckRow>& rows,
                       TableDetail detail);

// `text` with every quoted name ('hip') emptied to '' and every number (3, -0.25, 1e-05) that
// is not part of a word replaced by "#": two rows with the same shape make the same finding
// about different elements.
std::string FindingShape(const std::string& text);

// Wraps `text` at `width` columns, each line prefixed with `indent` and ending in a newline.
std::string Wrap(const std::string& text, std::size_t width, const std::string& indent);

}  // namespace plumb::cli

#endif  // PLUMB_APPS_PLUMB_SUMMARY_H_
