// One audit check's rows, for the audit's tests: every row of the check in the audit of a model,
// the findings (WARN and FAIL) among them, and a text listing them for a failure message.

#ifndef PLUMB_TESTS_AUDIT_CHECK_ROWS_H_
#define PLUMB_TESTS_AUDIT_CHECK_ROWS_H_

#include <string>
#include <vector>

#include "plumb/audit.h"
#include "plumb/check.h"
#include "plumb/model.h"

namespace plumb::testing {

// The rows of check `id` (all statuses) in the audit of the model at `path`, default options.
inline std::vector<CheckRow> CheckRows(const std::string& path, const std::string& id) {
  std::vector<CheckRow> out;
  for (const CheckRow& row : Audit(Model::Load(path), AuditOptions{}).findings) {
    if (row.id == id) out.push_back(row);
  }
  return out;
}

// The WARN and FAIL rows of `rows`.
inline std::vector<CheckRow> FindingRows(const std::vector<CheckRow>& rows) {
  std::vector<CheckRow> out;
  for (const CheckRow& row : rows) {
    if (row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail) out.push_back(row);
  }
  return out;
}

// "STATUS element: measured | fix" a line per row.
inline std::string RowsText(const std::vector<CheckRow>& rows) {
  std::string out;
  for (const CheckRow& row : rows) {
    out += std::string(CheckStatusName(row.status)) + " " + row.About() + ": " +
           row.measured_text + " | " + row.fix + "\n";
  }
  return out;
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_AUDIT_CHECK_ROWS_H_
