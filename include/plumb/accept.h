// An accept list: the findings a team has reviewed and accepts, each with its reason, so that a
// check run in CI fails on what is new without losing sight of what was judged.
//
// The file is TOML, one [[accept]] table per accepted finding:
//   [[accept]]
//   check = "inertia.shape"          # the row's id
//   element = "body 'base_link'"    # what the row is about, without its id; omitted: the model
//   status = "WARN"                 # optional: only while it is a WARN (or "FAIL")
//   reason = "CAD inertia checked against the vendor datasheet, 2026-10"
//
// An entry accepts every WARN or FAIL row (never a PASS or a SKIP) whose id is `check`, that
// is about `element` as AcceptElement names it (the element's kind and name, never its id:
// ids shift as the model changes), and, when the entry has a status, that has it. An accepted
// row keeps its status and carries the reason (CheckRow::accepted); it counts apart and fails
// no run (CountUnaccepted). An entry that accepts no row is stale: the finding was fixed, the
// element renamed, or the finding changed status; it becomes a WARN row of its own
// (kAcceptStale), so that a list cannot outlive the defects it was written for.
//
// Example:
//   plumb::AcceptList accepted = plumb::LoadAcceptList("accept.toml");
//   plumb::AuditReport report = plumb::Audit(model, {});
//   plumb::ApplyAcceptList(accepted, &report.findings);
//   bool failed = plumb::CountUnaccepted(report.findings, plumb::CheckStatus::kFail) > 0;
//
// Thread-safety: plain data and functions that keep no state; LoadAcceptList only reads its
// file. Call them from any thread.

#ifndef PLUMB_INCLUDE_PLUMB_ACCEPT_H_
#define PLUMB_INCLUDE_PLUMB_ACCEPT_H_

#include <optional>
#include <string>
#include <vector>

#include "plumb/check.h"

namespace plumb {

// The id of the WARN row a stale entry becomes; its section is "accept".
inline constexpr const char* kAcceptStale = "accept.stale";

// One accepted finding.
struct AcceptEntry {
  std::string check;  // the row's id: "inertia.shape"
  // What the row is about as AcceptElement names it: "body 'base_link'", a subject such as
  // "geom 'foot' / geom 'floor'" or "BADQACC"; "" for a row about the whole model.
  std::string element;
  // Only rows of this status (kWarn or kFail); nullopt: either.
  std::optional<CheckStatus> status;
  std::string reason;  // why the finding is acceptable; never empty in a loaded list
  int line = 0;        // the line of the entry's [[accept]] in the file; 0: not from a file
};

struct AcceptList {
  std::string file;  // the file it was read from, as given; "" when made in code
  std::vector<AcceptEntry> entries;
};

// Reads an accept list from a TOML file (the format above). Every entry needs `check` and a
// non-empty `reason`; `element` names an element by kind and name, not by id ("body 'hand'
// (id 3)" is refused; an unnamed "body #3" is read but never accepts a row, and its stale row
// says to name the element). @throws IoError when the file cannot be read,
// ValueError naming the file, line and column of the problem for invalid TOML, an unknown key,
// a missing or empty entry, a value of the wrong type or an entry that repeats another.
AcceptList LoadAcceptList(const std::string& path);

// How an accept entry names what `row` is about: its element's kind and name ("body 'hand'"),
// "body #3" for an unnamed element, else its subject with every " (id N)" left out
// ("geom 'foot' / geom 'floor'"); "" for a row about the whole model.
std::string AcceptElement(const CheckRow& row);

// True when `entry` accepts `row`: a WARN or FAIL row with the entry's check, element and,
// when it has one, status.
bool Accepts(const AcceptEntry& entry, const CheckRow& row);

// Marks each row of `rows` that an entry of `list` accepts with that entry's reason
// (CheckRow::accepted; the first entry that accepts it wins), then appends one kAcceptStale
// WARN row per entry that accepted no row, naming the file and line of the entry, what it
// named, what became of it and what rows of its check there are. Apply it once per set of rows.
void ApplyAcceptList(const AcceptList& list, std::vector<CheckRow>* rows);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ACCEPT_H_
