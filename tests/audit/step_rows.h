// What the step-response tests read from an audit report (audit_step_test.cc,
// audit_step_corpus_test.cc): one actuator's row, its curve, and the rows that are findings.

#ifndef PLUMB_TESTS_AUDIT_STEP_ROWS_H_
#define PLUMB_TESTS_AUDIT_STEP_ROWS_H_

#include <gtest/gtest.h>

#include <string>

#include "plumb/audit.h"

namespace plumb::testing {

// The actuator.step_response row of actuator `name`; fails the test when there is none.
inline CheckRow StepRow(const AuditReport& r, const std::string& name) {
  for (const CheckRow& row : r.findings) {
    if (row.id == "actuator.step_response" && row.element.name == name) return row;
  }
  ADD_FAILURE() << "no actuator.step_response row of '" << name << "'";
  return {};
}

// The step response curve of actuator `name` (its start, target and samples); fails the test
// when there is none.
inline AuditCurve StepCurve(const AuditReport& r, const std::string& name) {
  for (const AuditCurve& c : r.step_responses) {
    if (c.label.find("'" + name + "'") != std::string::npos) return c;
  }
  ADD_FAILURE() << "no step response of '" << name << "'";
  return {};
}

// The WARN and FAIL actuator.step_response rows, one a line ("" when there are none).
inline std::string StepFindings(const AuditReport& r) {
  std::string out;
  for (const CheckRow& row : r.findings) {
    bool finding = row.status == CheckStatus::kWarn || row.status == CheckStatus::kFail;
    if (row.id == "actuator.step_response" && finding) {
      out += row.About() + ": " + row.measured_text + "\n";
    }
  }
  return out;
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_AUDIT_STEP_ROWS_H_
