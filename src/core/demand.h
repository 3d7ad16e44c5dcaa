// PLUMB_DEMAND(condition): an internal contract, checked in every build. When the condition
// is false it throws plumb::InternalError naming this file, the line and the condition's
// text, instead of going on with a state the code was not written for (or repairing it in
// silence). For contracts between plumb's own functions only: input from a caller is
// validated with a plumb::Error that says what to change.

#ifndef PLUMB_SRC_CORE_DEMAND_H_
#define PLUMB_SRC_CORE_DEMAND_H_

#include "plumb/error.h"

#define PLUMB_DEMAND(condition)                                          \
  do {                                                                   \
    if (!(condition)) throw ::plumb::InternalError(__FILE__, __LINE__, #condition); \
  } while (false)

#endif  // PLUMB_SRC_CORE_DEMAND_H_
