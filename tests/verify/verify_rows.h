// The verify tests' way to read a report's rows by id.

#ifndef PLUMB_TESTS_VERIFY_VERIFY_ROWS_H_
#define PLUMB_TESTS_VERIFY_VERIFY_ROWS_H_

#include <gtest/gtest.h>

#include <string>

#include "plumb/verify.h"

namespace plumb::testing {

// The row `id` of `report`; a failure of the calling test, and an empty row, when it has none.
inline const CheckRow& Find(const VerifyReport& report, const std::string& id) {
  for (const CheckRow& c : report.checks) {
    if (c.id == id) return c;
  }
  static CheckRow missing;
  ADD_FAILURE() << "no check " << id;
  return missing;
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_VERIFY_VERIFY_ROWS_H_
