// The tables of `plumb verify`, `plumb audit`, `plumb crosscheck` and a rehearsal (`plumb
// bridge` with a client): findings first, the rest counted.
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
#include "plumb/rehearse.h"
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

// A rehearsal's table (plumb/rehearse.h): the rows under their sections (assert, client,
// bridge), as verify's, each naming what it is about (an assertion's text); then how the client
// ended, with its output's last lines when it did not run to the end or the rehearsal failed
// (every line with kAll), each cut at 200 characters with bytes that would not print written
// \xNN; and the verdict line (RehearsalVerdict). kQuiet: the count line and the verdict line.
std::string RehearsalTable(const std::string& model, const RehearsalResult& result,
                           TableDetail detail, const std::string& how_to_see_all = "");

// How the client ended, in one clause: "exited early: exited with status 1 at t = 0.42 s
// (3.1 s of wall time)", "stopped: ended on SIGINT at t = 10.00 s (10.4 s of wall time)".
std::string DescribeClientEnding(const ClientEnding& client);

// The rehearsal's verdict in one line: "rehearsal PASS: 3 assertions hold; client stopped:
// ended on SIGINT at t = 10.00 s (10.4 s of wall time)"; a FAIL names how many assertions
// broke, the other rows that failed, the warnings, and a divergence.
std::string RehearsalVerdict(const RehearsalResult& result);

// Wraps `text` at `width` columns, each line prefixed with `indent` and ending in a newline.
std::string Wrap(const std::string& text, std::size_t width, const std::string& indent);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CHECK_TABLE_H_
