// The form of an assertion, "[REDUCE(]LHS[)] OP BOUND [during [a, b]]", apart from what its
// left-hand side denotes: plumb::ParseAssertion resolves LHS to the model's paths, a rehearsal
// (src/rehearse) to a motor signal as well.

#ifndef PLUMB_SRC_SCENARIO_ASSERTION_FORM_H_
#define PLUMB_SRC_SCENARIO_ASSERTION_FORM_H_

#include <functional>
#include <string>
#include <string_view>

#include "plumb/model.h"
#include "plumb/scenario.h"

namespace plumb::internal {

// Reads LHS (trimmed, the reduction's parentheses taken off) into `a` (its paths, for a path).
// @throws ValueError / PathError quoting a->text.
using AssertionResolver = std::function<void(std::string_view lhs, Assertion* a)>;

// Parses the reduction, the comparison, the bound and the window of `text`, then calls
// `resolve` with its left-hand side. @throws ValueError quoting `text`, and what `resolve`
// throws.
Assertion ParseAssertionForm(const std::string& text, const AssertionResolver& resolve);

// ParseAssertion's resolver: `lhs` as the model's paths ('*' expanded, each scalar one).
// @throws PathError.
void ResolvePaths(const Model& model, std::string_view lhs, Assertion* a);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_SCENARIO_ASSERTION_FORM_H_
