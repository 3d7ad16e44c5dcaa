// The tables of `plumb verify` and `plumb audit`: findings first, the rest counted.
//
// Example:
//   std::string text = plumb::AuditTable(plumb::Audit(model, {}), plumb::TableDetail::kFindings);
//
// Thread-safety: pure functions of their arguments; they throw nothing of plumb's own.

#ifndef PLUMB_INCLUDE_PLUMB_CHECK_TABLE_H_
#define PLUMB_INCLUDE_PLUMB_CHECK_TABLE_H_

#include <string>
#include <vector>

#include "plumb/audit.h"
#include "plumb/check.h"
#include "plumb/crosscheck.h"
#include "plumb/verify.h"

namespace plumb {

// How much of a check table to print: the findings (FAIL and WARN rows, SKIPs grouped by
// reason, PASS rows counted), every row, or the count line alone.
enum class TableDetail { kFindings, kAll, kQuiet };

// A table: `title` (a line), the rows `detail` asks for, and the count line "N passed, W
// warned, F failed, S skipped", saying that PASS rows were left out and `how_to_see_all`
// (kQuiet: that line alone).
// `texts[i]` is how rows[i] prints on its own (status first, lines each ending in a newline);
// a row with an element names it at the end of its first line. A section heading "== section"
// starts where rows[i].section changes. By default SKIPs sharing a reason (their explanation)
// become one row, "SKIP  8 checks skipped: REASON" with their ids below; and FAIL or WARN rows
// that make the same finding (section, id, status and CheckRow::finding) about several
// elements of one kind become one row, "WARN  actuator.limits  12 actuators alike: NAMES",
// then the first row's text as the example ("e.g. actuator 'hip' (id 0): ...").
// An accepted row (CheckRow::accepted, plumb/accept.h) is never grouped, and counts apart: the
// count line ends ", N accepted" when there are any, and W and F count the rest.
std::string CheckTable(const std::string& title, const std::vector<CheckRow>& rows,
                       const std::vector<std::string>& texts, TableDetail detail,
                       const std::string& how_to_see_all = "");

// verify's table: each check's id and title, its measured value, reference and relative
// error, and its explanation. An accepted row reads "ACCEPT" where its status would, and ends
// with a line "WARN accepted: REASON".
std::string VerifyTable(const VerifyReport& report, TableDetail detail,
                        const std::string& how_to_see_all = "");

// audit's table, one section per layer: each finding's id and element, what was measured
// against which threshold, and the fix of a WARN or FAIL; an accepted finding reads "ACCEPT"
// where its status would, and "FAIL accepted: REASON" where its fix would.
std::string AuditTable(const AuditReport& report, TableDetail detail,
                       const std::string& how_to_see_all = "");

// crosscheck's table, one section per check: as verify's, each row naming its element, plus
// the engine and how the model was sent.
std::string CrosscheckTable(const CrosscheckReport& report, TableDetail detail,
                            const std::string& how_to_see_all = "");

// Wraps `text` at `width` columns, each line prefixed with `indent` and ending in a newline.
std::string Wrap(const std::string& text, std::size_t width, const std::string& indent);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CHECK_TABLE_H_
