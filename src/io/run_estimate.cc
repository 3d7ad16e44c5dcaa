// What a run will cost before it is spent (include/plumb/run_estimate.h).

#include "plumb/run_estimate.h"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "plumb/error.h"
#include "plumb/sample_writer.h"

namespace plumb {

RunEstimate EstimateRun(const Model& model, const std::vector<Assignment>& sets,
                        const RunSpec& spec, SampleFormat format) {
  RunEstimate e;
  Model probe = model.Clone();
  Data data(probe);
  ApplyAssignments(probe, data, sets);
  double dt = probe->opt.timestep;
  Schedule schedule = MakeSchedule(dt, spec.until, spec.every);
  e.steps = schedule.steps;
  e.rows = schedule.steps / schedule.stride + 1;
  // the steps: timed for 0.1 s or 200000 steps, whichever comes first (fewer are swayed by
  // the first steps' cache misses); a diverging or failing probe just ends it (the run
  // itself reports that)
  auto start = std::chrono::steady_clock::now();
  double elapsed = 0;
  try {
    while (e.probe_steps < std::min<long>(schedule.steps, 200'000) && elapsed < 0.1) {
      data.Step();
      ++e.probe_steps;
      if (e.probe_steps % 16 == 0) {
        elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
    }
  } catch (const Error&) {
  }
  elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double per_step = e.probe_steps > 0 ? elapsed / e.probe_steps : 0;
  // one row through the real writer, into memory: its size and its time
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* memory = open_memstream(&buffer, &size);
  double per_row = 0, row_bytes = 0;
  if (memory != nullptr) {
    {
      std::unique_ptr<SampleSink> writer = MakeSampleWriter(format, memory);
      std::vector<double> row(spec.columns.size(), -0.123456789012345);
      writer->Begin(spec.columns);
      std::fflush(memory);
      std::size_t header = size;
      auto t = std::chrono::steady_clock::now();
      constexpr int kRows = 1024;
      for (int i = 0; i < kRows; ++i) writer->Sample(row);
      std::fflush(memory);
      per_row = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count() / kRows;
      row_bytes = static_cast<double>(size - header) / kRows;
      writer->End();
    }
    std::fclose(memory);
    std::free(buffer);
  }
  e.seconds = per_step * e.steps + per_row * e.rows;
  e.bytes = row_bytes * e.rows;
  return e;
}

std::string DescribeEstimate(const RunEstimate& e, const std::string& format) {
  return fmt::format("{} steps and {} rows: about {:.0f} s and {} of {} (from a {}-step probe)",
                     e.steps, e.rows, e.seconds, FormatBytes(e.bytes), format, e.probe_steps);
}

std::string FormatBytes(double b) {
  return b < 1e3   ? fmt::format("{:.0f} B", b)
         : b < 1e6 ? fmt::format("{:.0f} kB", b / 1e3)
         : b < 1e9 ? fmt::format("{:.0f} MB", b / 1e6)
                   : fmt::format("{:.1f} GB", b / 1e9);
}

std::string FormatDuration(double seconds) {
  if (seconds < 120) return fmt::format("{:.0f} s", seconds);
  if (seconds < 7200) return fmt::format("{:.0f} min", seconds / 60);
  if (seconds < 172800) return fmt::format("{:.1f} h", seconds / 3600);
  return fmt::format("{:.1f} days", seconds / 86400);
}

}  // namespace plumb
