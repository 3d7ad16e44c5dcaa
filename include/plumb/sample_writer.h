// Writing a run's samples as they arrive: a fixed-width table, CSV or JSON lines, and the
// CSV number and field rules every plumb command follows.
//
// Thread-safety: the CSV functions are pure. A sink from MakeSampleWriter serves one run at a
// time; sinks writing to different streams may run on different threads. A sink's Sample and
// End @throws IoError when the stream cannot be written (disk full, a closed pipe); the CSV
// functions throw nothing.

#ifndef PLUMB_INCLUDE_PLUMB_SAMPLE_WRITER_H_
#define PLUMB_INCLUDE_PLUMB_SAMPLE_WRITER_H_

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "plumb/run.h"

namespace plumb {

// Output formats of sampled rows.
enum class SampleFormat {
  kTable,  // fixed-width columns, 5 decimals: the chapter's printout
  kCsv,    // header of path names, then the shortest text that reads back exactly
  kJsonl,  // one JSON object per sample, keys are path names
};

// CSV as every plumb command writes it. A number is the shortest text that reads back as
// exactly `v` (0.3, not 0.29999999999999999; std::to_chars, faster than printf, which matters
// when every step is a row), and NaN (not measured) is an empty field. A text field is
// quoted (RFC 4180) when it holds a comma, quote or newline.
void AppendCsvNumber(std::string* out, double v);
std::string CsvNumber(double v);
std::string CsvField(const std::string& text);
// A CSV line of text fields (CsvField each), with its newline: a header.
std::string CsvLine(const std::vector<std::string>& fields);

// A sink writing rows to `out` (not owned) in `format`. Rows are written as they
// arrive; nothing is kept in memory. Write errors surface as IoError from End().
std::unique_ptr<SampleSink> MakeSampleWriter(SampleFormat format, std::FILE* out);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_SAMPLE_WRITER_H_
