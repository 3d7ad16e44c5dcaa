#include "core/fields.h"

#include <cstddef>
#include <iterator>
#include <limits>
#include <string_view>

namespace plumb::internal {
namespace {

using compat::ElemType;
using compat::ElemTypeOf;

[[maybe_unused]] long One(const mjModel*) { return 1; }

// Rows of an array whose filled part is counted by mjData rather than allocated by
// mjModel: no fixed bound at compile time; current_rows() gives the rows now.
[[maybe_unused]] long Unbounded(const mjModel*) { return std::numeric_limits<int>::max(); }

// How the rows of an arena array are counted (3.x): the size's name, the rows allocated
// and, for sizes of mjData, the rows filled at a state.
struct ArenaRows {
  const char* kind;
  long (*allocated)(const mjModel*);
  long (*now)(const mjModel*, const mjData*);
};

// For arrays allocated for the most constraints or contacts a step may hold (2.2.2's
// njmax and nconmax rows), the rows filled at the state of `d`; nullptr for the rest.
[[maybe_unused]] long (*CurrentRows(std::string_view row_kind))(const mjModel*, const mjData*) {
  if (row_kind == "njmax") return [](const mjModel*, const mjData* d) -> long { return d->nefc; };
  if (row_kind == "nconmax") return [](const mjModel*, const mjData* d) -> long { return d->ncon; };
  return nullptr;
}

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Winvalid-offsetof"

// One row of the tables below: a FieldInfo with its strings as literals. The tables are
// plain arrays (one X-macro expansion each), turned into FieldInfo by one loop: a function
// that pushed each of the ~600 fields into the vector directly took the compiler 90 s at -O3.
struct RawField {
  const char* name;
  FieldSource source;
  ElemType type;
  std::size_t offset;
  const char* row_kind;
  long (*rows)(const mjModel*);
  long (*cols)(const mjModel*);
  long (*current_rows)(const mjModel*, const mjData*);
};

void Append(std::vector<FieldInfo>& f, const RawField* raw, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const RawField& r = raw[i];
    f.push_back({r.name, r.source, r.type, r.offset, r.row_kind, r.rows, r.cols, r.current_rows});
  }
}

// model arrays: rows are a size field of mjModel, columns an expression of them
const RawField kModelArrays[] = {
#define X(type, name, nr, nc)                                                                \
  {#name,                                                                                    \
   FieldSource::kModelArray,                                                                 \
   ElemTypeOf<type>(),                                                                       \
   offsetof(mjModel, name),                                                                  \
   #nr,                                                                                      \
   [](const mjModel* m) -> long { return m->nr; },                                           \
   [](const mjModel* m) -> long {                                                            \
     MJMODEL_POINTERS_PREAMBLE(m)                                                            \
     return nc;                                                                              \
   },                                                                                        \
   nullptr},
    MJMODEL_POINTERS
#undef X
};

// model sizes (nq, nv, nbody, ...)
const RawField kModelSizes[] = {
#define X(name)                                                                              \
  {#name, FieldSource::kModelSize, ElemTypeOf<decltype(mjModel::name)>(),                    \
   offsetof(mjModel, name), "", One, One, nullptr},
    PLUMB_MJMODEL_SIZES
#undef X
};

// data arrays
const RawField kDataArrays[] = {
#define X(type, name, nr, nc)                                                                \
  {#name,                                                                                    \
   FieldSource::kDataArray,                                                                  \
   ElemTypeOf<type>(),                                                                       \
   offsetof(mjData, name),                                                                   \
   #nr,                                                                                      \
   [](const mjModel* m) -> long { return m->nr; },                                           \
   [](const mjModel* m) -> long {                                                            \
     PLUMB_MJDATA_POINTERS_PREAMBLE(m)                                                       \
     return nc;                                                                              \
   },                                                                                        \
   CurrentRows(#nr)},
    MJDATA_POINTERS
#undef X
};

#ifdef PLUMB_MJDATA_ARENA_POINTERS
// data arrays in the arena (3.x): rows are a size of mjModel (MJ_M) or of mjData (MJ_D)
#pragma push_macro("MJ_M")
#pragma push_macro("MJ_D")
#undef MJ_M
#undef MJ_D
#define MJ_M(n)                                                \
  ArenaRows {                                                  \
#n, [](const mjModel* m) -> long { return m->n; }, nullptr \
  }
#define MJ_D(n)                                                                 \
  ArenaRows {                                                                   \
#n, Unbounded, [](const mjModel*, const mjData* d) -> long { return d->n; } \
  }
// MuJoCo clears every arena pointer at the start of a step and allocates only those the
// step needs: a null pointer holds no rows
const RawField kDataArenaArrays[] = {
#define X(type, name, nr, nc)                                                                \
  {#name,                                                                                    \
   FieldSource::kDataArray,                                                                  \
   ElemTypeOf<type>(),                                                                       \
   offsetof(mjData, name),                                                                   \
   (nr).kind,                                                                                \
   (nr).allocated,                                                                           \
   [](const mjModel*) -> long { return nc; },                                                \
   [](const mjModel* m, const mjData* d) -> long {                                           \
     ArenaRows r = nr;                                                                       \
     if (!d->name) return 0;                                                                 \
     return r.now ? r.now(m, d) : r.allocated(m);                                            \
   }},
    PLUMB_MJDATA_ARENA_POINTERS
#undef X
};
#pragma pop_macro("MJ_D")
#pragma pop_macro("MJ_M")
#endif

// data scalars (time, ncon, ...) and the energy vector
const RawField kDataScalars[] = {
#define X(type, name)                                                                        \
  {#name, FieldSource::kDataScalar, ElemTypeOf<type>(), offsetof(mjData, name), "", One, One, \
   nullptr},
    MJDATA_SCALAR
#undef X
    {"energy", FieldSource::kDataScalar, ElemType::kNum, offsetof(mjData, energy), "", One,
     [](const mjModel*) -> long { return 2; }, nullptr},
};

// Every field, in the order of mujoco/mjxmacro.h's tables.
std::vector<FieldInfo> BuildFields() {
  std::vector<FieldInfo> f;
  Append(f, kModelArrays, std::size(kModelArrays));
  Append(f, kModelSizes, std::size(kModelSizes));

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

  Append(f, kDataArrays, std::size(kDataArrays));
#ifdef PLUMB_MJDATA_ARENA_POINTERS
  Append(f, kDataArenaArrays, std::size(kDataArenaArrays));
#endif
  Append(f, kDataScalars, std::size(kDataScalars));
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

double ReadElement(ElemType type, const void* at) {
  switch (type) {
    case ElemType::kNum:
      return *static_cast<const mjtNum*>(at);
    case ElemType::kInt:
      return *static_cast<const int*>(at);
    case ElemType::kInt64:
      return static_cast<double>(*static_cast<const long long*>(at));
    case ElemType::kByte:
      return *static_cast<const mjtByte*>(at);
    case ElemType::kBool:
      return *static_cast<const bool*>(at) ? 1 : 0;
    case ElemType::kFloat:
      return *static_cast<const float*>(at);
    case ElemType::kChar:
      return *static_cast<const char*>(at);
    case ElemType::kOther:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

bool WriteElement(ElemType type, void* at, double value) {
  switch (type) {
    case ElemType::kNum:
      *static_cast<mjtNum*>(at) = value;
      return true;
    case ElemType::kFloat:
      *static_cast<float*>(at) = static_cast<float>(value);
      return true;
    case ElemType::kInt:
      *static_cast<int*>(at) = static_cast<int>(value);
      return true;
    case ElemType::kInt64:
      *static_cast<long long*>(at) = static_cast<long long>(value);
      return true;
    case ElemType::kByte:
      *static_cast<mjtByte*>(at) = static_cast<mjtByte>(value);
      return true;
    case ElemType::kBool:
      *static_cast<bool*>(at) = value != 0;
      return true;
    case ElemType::kChar:
    case ElemType::kOther:
      break;
  }
  return false;
}

}  // namespace plumb::internal
