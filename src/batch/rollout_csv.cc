#include "plumb/rollout_csv.h"

#include "plumb/sample_writer.h"

namespace plumb {

std::vector<std::string> RolloutCsvColumns(const std::vector<std::string>& params,
                                           const std::vector<std::string>& metrics) {
  std::vector<std::string> columns = {"rollout"};
  columns.insert(columns.end(), params.begin(), params.end());
  columns.insert(columns.end(), metrics.begin(), metrics.end());
  for (const char* c : {"diverged", "diverged_at", "problem"}) columns.push_back(c);
  return columns;
}

std::string RolloutCsvRow(const RolloutResult& r) {
  std::string out = std::to_string(r.index);
  for (double v : r.params) out += "," + CsvNumber(v);
  for (double v : r.metrics) out += "," + CsvNumber(v);
  out += r.diverged ? ",1," + CsvNumber(r.diverged_time) : ",0,";
  return out + "," + CsvField(r.problem) + "\n";
}

}  // namespace plumb
