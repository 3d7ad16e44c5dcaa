// The compiled model's NaN and infinite parameters, named by path. MuJoCo's compiler takes
// "nan" and "inf" in most attributes with at most a warning ("XML contains a 'NaN'"), and
// such a value poisons every step or only what it draws; verify and audit report them.

#include <fmt/format.h>

#include <cmath>

#include "core/fields.h"
#include "plumb/error.h"
#include "plumb/path.h"

namespace plumb {
using internal::FieldInfo;
using internal::Fields;
using internal::FieldSource;

namespace {

// The path naming flat element `i` of `field`: the row's path from ExpandPath (names rows by
// name, or by id when unnamed) with the column appended, else the field and the flat index.
std::string ElementPath(const Model& model, const FieldInfo& field, long i) {
  if (field.row_kind.empty()) {
    long cols = field.cols(model.get());
    return cols == 1 ? field.name : fmt::format("{}[{}]", field.name, i);
  }
  try {
    for (const Path& row : ExpandPath(model, field.name + "[*]")) {
      if (i < row.first || i >= row.first + row.count) continue;
      return row.count == 1 ? row.text : fmt::format("{}[{}]", row.text, i - row.first);
    }
  } catch (const Error&) {
  }
  return fmt::format("{} (element {})", field.name, i);
}

}  // namespace

NonFiniteValues NonFiniteParameters(const Model& model, std::size_t max) {
  const mjModel* m = model.get();
  NonFiniteValues out;
  for (const FieldInfo& field : Fields()) {
    if (field.source != FieldSource::kModelArray && field.source != FieldSource::kOption) continue;
    if (field.type != compat::ElemType::kNum && field.type != compat::ElemType::kFloat) continue;
    const void* base = FieldBase(field, m, nullptr);
    if (base == nullptr) continue;
    long n = field.rows(m) * field.cols(m);
    for (long i = 0; i < n; ++i) {
      double v = field.type == compat::ElemType::kNum ? static_cast<const mjtNum*>(base)[i]
                                                      : static_cast<const float*>(base)[i];
      if (std::isfinite(v)) continue;
      if (out.first.size() < max) {
        out.first.push_back(fmt::format("{} = {}", ElementPath(model, field, i), v));
      }
      ++out.total;
    }
  }
  return out;
}

}  // namespace plumb
