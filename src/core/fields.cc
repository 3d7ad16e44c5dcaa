#include "core/fields.h"

#include <cstddef>

namespace plumb {
namespace {

using compat::ElemType;
using compat::ElemTypeOf;

[[maybe_unused]] long One(const mjModel*) { return 1; }

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Winvalid-offsetof"

std::vector<FieldInfo> BuildFields() {
  std::vector<FieldInfo> f;

  // model arrays: rows are a size field of mjModel, columns an expression of them
#define X(type, name, nr, nc)                                                                     \
  f.push_back({#name, FieldSource::kModelArray, ElemTypeOf<type>(), offsetof(mjModel, name), #nr, \
               [](const mjModel* m) -> long { return m->nr; },                                    \
               [](const mjModel* m) -> long {                                                     \
                 MJMODEL_POINTERS_PREAMBLE(m)                                                     \
                 return nc;                                                                       \
               }});
  MJMODEL_POINTERS
#undef X

  // model sizes (nq, nv, nbody, ...)
#define X(name)                                                                       \
  f.push_back({#name, FieldSource::kModelSize, ElemTypeOf<decltype(mjModel::name)>(), \
               offsetof(mjModel, name), "", One, One});
  PLUMB_MJMODEL_SIZES
#undef X

  // options
  for (const compat::OptionField& o : compat::OptionFields()) {
    long (*cols)(const mjModel*) = One;
    switch (o.size) {
      case 1:
        break;
      case 2:
        cols = [](const mjModel*) -> long { return 2; };
        break;
      case 3:
        cols = [](const mjModel*) -> long { return 3; };
        break;
      case 5:
        cols = [](const mjModel*) -> long { return 5; };
        break;
      default:
        cols = nullptr;
    }
    if (!cols) continue;  // no vector option of another length exists today
    f.push_back({std::string("opt.") + o.name, FieldSource::kOption, o.type,
                 offsetof(mjModel, opt) + o.offset, "", One, cols});
  }

  // data arrays
#define X(type, name, nr, nc)                                                                   \
  f.push_back({#name, FieldSource::kDataArray, ElemTypeOf<type>(), offsetof(mjData, name), #nr, \
               [](const mjModel* m) -> long { return m->nr; },                                  \
               [](const mjModel* m) -> long {                                                   \
                 MJDATA_POINTERS_PREAMBLE(m)                                                    \
                 return nc;                                                                     \
               }});
  MJDATA_POINTERS
#undef X

  // data scalars (time, ncon, ...) and the energy vector
#define X(type, name)                                                                           \
  f.push_back({#name, FieldSource::kDataScalar, ElemTypeOf<type>(), offsetof(mjData, name), "", \
               One, One});
  MJDATA_SCALAR
#undef X
  f.push_back({"energy", FieldSource::kDataScalar, ElemType::kNum, offsetof(mjData, energy), "",
               One, [](const mjModel*) -> long { return 2; }});
  return f;
}

#pragma GCC diagnostic pop

}  // namespace

const std::vector<FieldInfo>& Fields() {
  static const std::vector<FieldInfo> fields = BuildFields();
  return fields;
}

const FieldInfo* FindField(std::string_view name) {
  for (const FieldInfo& field : Fields()) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

const void* FieldBase(const FieldInfo& field, const mjModel* m, const mjData* d) {
  switch (field.source) {
    case FieldSource::kModelArray:
      return *reinterpret_cast<void* const*>(reinterpret_cast<const char*>(m) + field.offset);
    case FieldSource::kModelSize:
    case FieldSource::kOption:
      return reinterpret_cast<const char*>(m) + field.offset;
    case FieldSource::kDataArray:
      return *reinterpret_cast<void* const*>(reinterpret_cast<const char*>(d) + field.offset);
    case FieldSource::kDataScalar:
      return reinterpret_cast<const char*>(d) + field.offset;
  }
  return nullptr;
}

std::size_t ElemSize(compat::ElemType type) {
  switch (type) {
    case ElemType::kNum:
      return sizeof(mjtNum);
    case ElemType::kInt:
      return sizeof(int);
    case ElemType::kInt64:
      return sizeof(long long);
    case ElemType::kByte:
      return sizeof(mjtByte);
    case ElemType::kBool:
      return sizeof(bool);
    case ElemType::kFloat:
      return sizeof(float);
    case ElemType::kChar:
      return sizeof(char);
    case ElemType::kOther:
      return 0;
  }
  return 0;
}

}  // namespace plumb
