// Where a schema violation MuJoCo reports is, and what was meant: MuJoCo names the element
// and a line, but for an element of an included file (<include file="...">) the line is 0
// and no file is named. plumb finds the attribute in the model's files and offers the
// attributes the element takes that are nearest the misspelled one (from MuJoCo's own schema,
// mj_printSchema).

#ifndef PLUMB_SRC_CORE_SCHEMA_ERROR_H_
#define PLUMB_SRC_CORE_SCHEMA_ERROR_H_

#include <string>
#include <vector>

namespace plumb::internal {

// The attributes MuJoCo's schema allows on `element` ("geom"), from every place the element
// may stand; empty for an element the schema does not know.
std::vector<std::string> SchemaAttributes(const std::string& element);

// For MuJoCo's error text `error` on the model file `path` ("Schema violation: unrecognized
// attribute: 'sise'\nElement 'geom', line 0"): one sentence naming the file, the model's own
// or one it includes, and the line the attribute stands on, and the attributes the element
// takes that are nearest ("did you mean: size?"). "" when the error is no unrecognized
// attribute, or neither the place nor a near attribute is found.
std::string SchemaErrorPlace(const std::string& error, const std::string& path);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_SCHEMA_ERROR_H_
