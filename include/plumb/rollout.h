// Rollouts with domain randomization: many runs of one model, each with physical
// parameters drawn from distributions, measured with metrics, deterministically.
//
// Example:
//   plumb::RolloutSpec spec;
//   spec.count = 1000;
//   spec.until = 2;
//   spec.randomize = {plumb::ParseRandomization(model, "body_mass[*]=*U(0.9,1.1)")};
//   spec.metrics = {plumb::ParseMetric(model, "xpos[torso][2]@2")};
//   plumb::Rollout(model, spec, [](const plumb::RolloutResult& r) { ... });  // index order
//
// Thread-safety: Rollout, RolloutCases and RolloutPool::Run run on spec.threads threads of a TBB
// arena, each on its own copy of `model`, which is only read: calls may run at once, also on one
// Model, but a RolloutPool runs one batch at a time. `emit` is called on the calling thread,
// spec.progress on the workers. The calling thread may run rollouts too: its pending MuJoCo
// warnings are dropped (TakeMujocoWarnings). The other functions keep no state.

#ifndef PLUMB_INCLUDE_PLUMB_ROLLOUT_H_
#define PLUMB_INCLUDE_PLUMB_ROLLOUT_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "plumb/metric.h"

namespace plumb {

// A distribution for a parameter: U(a,b), N(mu,sigma), LogU(a,b); prefixed `*` it scales
// the nominal value (`*U(0.9,1.1)`), prefixed `+` it offsets it (`+N(0,0.01)`).
struct Distribution {
  enum class Kind { kUniform, kNormal, kLogUniform } kind = Kind::kUniform;
  enum class Mode { kAbsolute, kScale, kOffset } mode = Mode::kAbsolute;
  double a = 0, b = 1;  // U/LogU: bounds; N: mean, standard deviation
  std::string text;
  // The value for nominal value `nominal` given a uniform `u` in (0, 1) and a standard
  // normal `z` (only one of them is used, by kind).
  double Apply(double nominal, double u, double z) const;
};

// @throws ValueError naming the text, e.g. for LogU with a bound <= 0 or N with sigma < 0.
Distribution ParseDistribution(std::string_view text);

// `PATH=DIST`, the path's rows may be `*`: one random parameter per matched element.
struct Randomization {
  std::string text;
  std::vector<Path> paths;  // single elements, model parameters only
  Distribution dist;
};

// @throws PathError / ValueError; state paths (qpos, ...) are allowed too and are drawn
// after the model parameters.
Randomization ParseRandomization(const Model& model, std::string_view text);

struct RolloutSpec {
  long count = 1;    // rollouts; indices 0 .. count-1
  double until = 2;  // s
  std::uint64_t seed = 0;
  int threads = 1;
  std::vector<Assignment> sets;  // the nominal scenario
  std::vector<Randomization> randomize;
  // Control noise, a fraction of each ctrlrange: before every step ctrl = centre +
  // noise*radius*(2u-1), the centre the start's ctrl (CtrlNoiseCentre: a servo holds the
  // start's pose), radius half the ctrlrange (1 when unlimited), u uniform and keyed by
  // (seed, rollout, actuator, step), so each rollout has its own noise, the same for any
  // thread count or shard.
  double ctrl_noise = 0;
  std::vector<Metric> metrics;  // all measured in the one run of each rollout
  // Which indices to run: those i with i % shard_count == shard_index.
  long shard_index = 0, shard_count = 1;
  // Indices to skip (already stored, for --resume); sorted.
  std::vector<long> skip;
  // Called after each finished rollout with (done, total), from a worker thread.
  std::function<void(long, long)> progress;
  // For a caller that runs the same rollouts elsewhere (plumb crosscheck): called on the
  // worker thread for rollout `index` with step 0 once its start is made (draws, state,
  // mj_forward: `work` holds the rollout's parameters), then before each step k = 1, 2, ...
  // with the controls that step takes. Empty: not called.
  std::function<void(long index, long step, const Model& work, const mjData* data)> observe;
};

struct RolloutResult {
  long index = 0;
  std::vector<double> params;   // sampled values, in the order of the expanded paths
  std::vector<double> metrics;  // NaN where a metric could not be measured
  bool diverged = false;
  double diverged_time = 0;  // s
  std::string problem;       // divergence or measurement problem
  std::string warnings;      // MuJoCo warnings of the run: "CONTACTFULL x3 (t = 0.1 s); ..."
};

// Names of the sampled parameters, in RolloutResult::params order.
std::vector<std::string> ParameterNames(const RolloutSpec& spec);

// Runs the rollouts of the spec's shard, skipping `skip`, and calls `emit` once per
// rollout in increasing index order (from the calling thread). Memory does not grow
// with count: work is done in chunks. Results are bit-identical whatever the thread
// count, shard split or skipped set: every random number is keyed by (seed, rollout
// index, parameter). @throws ValueError for a bad spec; Interrupted when `stop` asks (every
// rollout that finished was emitted: those after the first unfinished one last, still in
// increasing index order, with gaps); MujocoError; what `emit` throws.
void Rollout(const Model& model, const RolloutSpec& spec,
             const std::function<void(const RolloutResult&)>& emit, const StopToken& stop = {});

// Runs exactly the rollouts `indices` (any order, no duplicates) and calls `emit` once per
// rollout in the order given, from the calling thread; the building block of Rollout and
// of distributing rollouts over processes. Ignores spec.shard_* and spec.skip, and checks
// nothing of `spec` (ValidateRolloutSpec does): spec.threads < 1 ends in InternalError.
// @throws ValueError / PathError when the model refuses spec.sets; Interrupted when `stop`
// asks (every rollout that finished was emitted, as Rollout says); MujocoError; what `emit`
// throws.
void RolloutCases(const Model& model, const RolloutSpec& spec, const std::vector<long>& indices,
                  const std::function<void(const RolloutResult&)>& emit,
                  const StopToken& stop = {});

// RolloutCases for many batches of indices (chunks of a long run, or work an MPI rank is
// handed): the worker threads' model copies and data are made once and kept between
// calls. `model` and `spec` must outlive the pool. The constructor checks only spec.threads
// (@throws ValueError when < 1); Run @throws as RolloutCases does.
class RolloutPool {
 public:
  RolloutPool(const Model& model, const RolloutSpec& spec);
  ~RolloutPool();
  RolloutPool(const RolloutPool&) = delete;
  RolloutPool& operator=(const RolloutPool&) = delete;

  void Run(const std::vector<long>& indices, const std::function<void(const RolloutResult&)>& emit,
           const StopToken& stop = {});
  // Runs the rollouts of spec's shard that spec.skip leaves, in index order, as Rollout does:
  // their indices are made as they are run, so memory does not grow with spec.count.
  void RunShard(const std::function<void(const RolloutResult&)>& emit, const StopToken& stop = {});

 private:
  // Runs `total` rollouts, whose indices `next` hands out (up to its second argument at a time).
  void Stream(long total, const std::function<void(std::vector<long>*, std::size_t)>& next,
              const std::function<void(const RolloutResult&)>& emit, const StopToken& stop);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The number of rollouts in spec's shard: the indices i < spec.count with
// i % shard_count == shard_index; ShardToRun leaves out those in spec.skip. Counted, never
// listed (a count of 2^53 takes no time).
long ShardSize(const RolloutSpec& spec);
long ShardToRun(const RolloutSpec& spec);

// The ctrl control noise is centred on: the start's ctrl, as `d` holds it once the start is
// written, each clamped to its ctrlrange (MuJoCo clamps a ctrl outside it).
std::vector<double> CtrlNoiseCentre(const mjModel* m, const mjData* d);

// Checks control noise as RolloutSpec::ctrl_noise takes it (rollout and crosscheck).
// @throws ArgumentError (argument "ctrl_noise") unless 0 <= ctrl_noise <= 1 (NaN is refused).
void RequireCtrlNoise(double ctrl_noise);

// Checks a spec (counts, shard, until as RequireStepsToReach, control noise, metric times).
// @throws ValueError.
void ValidateRolloutSpec(const Model& model, const RolloutSpec& spec);

// Serialises a result to bytes and back, for sending it between processes. DecodeResult
// @throws ValueError when `bytes` is truncated or damaged.
std::string EncodeResult(const RolloutResult& result);
RolloutResult DecodeResult(const std::string& bytes);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_ROLLOUT_H_
