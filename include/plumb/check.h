// One row of a check: the result type every check of plumb writes (verify, audit, and the
// checks built on them), and the writers read.
//
// A row holds numbers as numbers, with their units: the measured value, the reference or
// threshold it is held against, and their relative error. The texts beside them say what a
// number alone cannot (which quantity, in what context, with the check's own digits), so a
// writer never parses a row's text back.
//
// Example:
//   plumb::CheckRow row;
//   row.id = "inertia.tiny_mass";
//   row.status = plumb::CheckStatus::kWarn;
//   row.element = {"body", "hand", 3};
//   row.measured = {2e-6, ""};  // of the total mass
//   row.reference = {1e-4, ""};
//   plumb::ElementLabel(row.element)  // "body 'hand' (id 3)"
//
// Thread-safety: plain data and pure functions; they throw nothing.

#ifndef PLUMB_INCLUDE_PLUMB_CHECK_H_
#define PLUMB_INCLUDE_PLUMB_CHECK_H_

#include <cmath>
#include <string>
#include <vector>

namespace plumb {

enum class CheckStatus { kPass, kWarn, kFail, kSkip };
const char* CheckStatusName(CheckStatus status);  // "PASS", "WARN", "FAIL", "SKIP"

// A number and its unit. `value` is NaN when the quantity is not one number (a row's text
// then says what was measured).
struct Quantity {
  double value = NAN;
  std::string unit;  // "kg", "kg*m^2", "rad", "s"; "" for a ratio or a count
  bool known() const { return std::isfinite(value); }
};

// The model element a row judges. `kind` is empty when the row is about the whole model or
// about several elements (CheckRow::subject then names them).
struct CheckElement {
  std::string kind;  // the noun: "body", "joint", "actuator", "geom", ...
  std::string name;  // "" when unnamed
  int id = -1;       // -1 for what has a name but no id (an option, a flag)
  bool empty() const { return kind.empty(); }
};

// How an element reads in text: "body 'hand' (id 3)", or "body #3" when unnamed, or "option
// 'solver'" for a named element without an id (id -1); "" for none.
std::string ElementLabel(const CheckElement& element);

struct CheckRow {
  CheckStatus status = CheckStatus::kSkip;
  std::string id;       // the check: "convergence", "inertia.tiny_mass"
  std::string section;  // the group it belongs to (audit's layer: "inertia"); "" for none
  std::string title;    // what the check tests, one line ("" when the id says it)
  // Which of the check's findings this row makes, when one check can make several
  // ("ctrl unlimited" against "ctrl limited, force unlimited"): rows of the same section,
  // id, status and finding about different elements say the same thing (a table groups them).
  std::string finding;
  CheckElement element;
  std::string subject;  // what the row is about when it is not one element ("" for the model)
  Quantity measured;
  Quantity reference;      // the reference value, or the threshold, it is held against
  bool threshold = false;  // the reference is a bound to respect, not a value to match
  double rel_error = NAN;  // |measured - reference| / |reference| where that applies
  // The measurement and the reference as a reader sees them: the numbers with the check's
  // digits and units, and what they are ("com 0.31 m outside its geoms", "<= 0.05 m").
  // Empty: nothing measured (a SKIP) or no reference.
  std::string measured_text;
  std::string reference_text;
  std::string explanation;  // what the result means; for a SKIP, why it was skipped
  std::string fix;          // what to do about a WARN or FAIL ("" when nothing to do)
  // Why a reviewed accept list accepts this WARN or FAIL (plumb/accept.h); "" when it is not
  // accepted. An accepted row keeps its status and counts apart: it fails no run.
  std::string accepted;

  // What the row is about as text: the element's label, else the subject ("" for the model).
  std::string About() const;
};

// How many of `rows` have `status`, accepted or not.
int CountStatus(const std::vector<CheckRow>& rows, CheckStatus status);

// How many of `rows` have `status` and are not accepted (CheckRow::accepted): the rows that
// decide a run, and that the tables and JSON summaries count by status.
int CountUnaccepted(const std::vector<CheckRow>& rows, CheckStatus status);

// How many of `rows` are accepted.
int CountAccepted(const std::vector<CheckRow>& rows);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_CHECK_H_
