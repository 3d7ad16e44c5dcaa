// What the actuator.timescale tests share (audit_timescale_test.cc, audit_saturation_test.cc):
// the check's rows on a model, the row about one element, and a corpus robot with every
// occurrence of some texts replaced, in a folder of the test's own.

#ifndef PLUMB_TESTS_AUDIT_TIMESCALE_FIXTURE_H_
#define PLUMB_TESTS_AUDIT_TIMESCALE_FIXTURE_H_

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "audit/check_rows.h"
#include "fixture.h"
#include "plumb/check_table.h"

namespace plumb::testing {

class TimescaleFixture : public ::testing::Test {
 protected:
  using Edits = std::vector<std::pair<std::string, std::string>>;

  static std::vector<CheckRow> Rows(const std::string& path) {
    return CheckRows(path, "actuator.timescale");
  }

  // The row about element `name`; nullptr when there is none.
  static const CheckRow* Named(const std::vector<CheckRow>& rows, const std::string& name) {
    for (const CheckRow& row : rows) {
      if (row.element.name == name) return &row;
    }
    return nullptr;
  }

  // Each `edits` pair applied to every occurrence of its first text (EditedModelCopy replaces
  // the first one per pair), in `dir` (the fixture's own folder when empty).
  std::string Edited(const std::string& path, const Edits& edits, const std::string& dir = "") {
    std::string xml = ReadFile(path);
    Edits all;
    for (const auto& edit : edits) {
      size_t n = 0;
      for (size_t at = xml.find(edit.first); at != std::string::npos;
           at = xml.find(edit.first, at + 1)) {
        ++n;
      }
      EXPECT_GT(n, 0u) << "no '" << edit.first << "' in " << path;
      all.insert(all.end(), n, edit);
    }
    return EditedModelCopy(path, all, dir.empty() ? dir_.path() : dir);
  }

  TempDir dir_;
};

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_AUDIT_TIMESCALE_FIXTURE_H_
