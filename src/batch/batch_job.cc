// A batch job as every front end runs it (include/plumb/batch_job.h).

#include "plumb/batch_job.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/path.h"
#include "plumb/rollout.h"

namespace plumb {
namespace {

// Runs `parse` on the user's `text` for `argument`: an ArgumentError or ValueError it throws
// becomes an ArgumentError naming `argument` and the text (the value it named, when it named
// one). PathError passes unchanged.
template <typename Parse>
auto NamedArgument(const char* argument, const std::string& text, Parse&& parse)
    -> decltype(parse()) {
  try {
    return parse();
  } catch (const ArgumentError& e) {
    throw ArgumentError(argument, e.value().empty() ? Quoted(text) : e.value(), e.problem());
  } catch (const ValueError& e) {
    throw ArgumentError(argument, Quoted(text), e.what());
  }
}

std::vector<Metric> ParseMetrics(const Model& model, const std::vector<std::string>& texts) {
  std::vector<Metric> out;
  for (const std::string& m : texts) {
    out.push_back(NamedArgument("metric", m, [&] { return ParseMetric(model, m); }));
  }
  return out;
}

// An assignment's warnings (Assignment::warnings) as notices naming the option's text.
void WarnAboutAxis(const std::string& subject, const std::vector<std::string>& warnings,
               Notices* notices) {
  for (const std::string& w : warnings) {
    AddTo(notices, {NoticeLevel::kWarning, NoticeTopic::kStart, subject, w});
  }
}

}  // namespace

void SayCtrlNoiseCentre(const Model& model, const RolloutSpec& spec, Notices* notices) {
  const mjModel* m = model.get();
  if (!(spec.ctrl_noise > 0) || m->nu == 0 || !notices) return;
  bool sets_ctrl = std::any_of(spec.sets.begin(), spec.sets.end(),
                               [](const Assignment& a) { return a.path.field == "ctrl"; });
  std::vector<std::string> servos, clamped;
  Model work = model.Clone();  // WriteState takes a model it may write
  Data data(work);
  WriteState(work, data, spec.sets);
  std::vector<double> centre = CtrlNoiseCentre(m, data.get());
  for (int j = 0; j < m->nu; ++j) {
    std::string name = model.Name(mjOBJ_ACTUATOR, j);
    std::string label = name.empty() ? "#" + std::to_string(j) : "'" + name + "'";
    // a position servo (or pid) reads ctrl as the position it drives towards
    bool servo = m->actuator_gaintype[j] == compat::kGainPid ||
                 (m->actuator_biastype[j] == mjBIAS_AFFINE &&
                  m->actuator_biasprm[mjNBIAS * j + 1] != 0);
    if (servo) servos.push_back(label);
    if (centre[j] != data->ctrl[j]) {
      clamped.push_back(fmt::format("{} (ctrl {:g}: centred on {:g})", label, data->ctrl[j],
                                    centre[j]));
    }
  }
  auto list = [](const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < 3; ++i) out += (i ? ", " : "") + names[i];
    if (names.size() > 3) out += fmt::format(" and {} more", names.size() - 3);
    return out;
  };
  if (!sets_ctrl && !servos.empty()) {
    AddTo(notices,
          {NoticeLevel::kNote, NoticeTopic::kStart, "ctrl noise",
           fmt::format("the start sets no ctrl (no keyframe, no ctrl set), so the control noise "
                       "is centred on ctrl 0, which {} position servo{} ({}) read as a target "
                       "position of 0, not as the start's pose; start from a keyframe with a "
                       "ctrl, or set ctrl, to centre the noise on the pose to hold.",
                       servos.size(), servos.size() == 1 ? "" : "s", list(servos))});
  }
  if (!clamped.empty()) {
    AddTo(notices, {NoticeLevel::kNote, NoticeTopic::kStart, "ctrl noise",
                    fmt::format("the start's ctrl lies outside the ctrlrange of {} actuator{} "
                                "({}): MuJoCo clamps it, and the control noise is centred on "
                                "the nearest end of the range.",
                                clamped.size(), clamped.size() == 1 ? "" : "s", list(clamped))});
  }
}

RolloutSpec ParseRolloutSpec(const Model& model, RolloutSpec spec, const BatchText& text,
                             Notices* notices) {
  for (const std::string& r : text.randomize) {
    spec.randomize.push_back(NamedArgument("randomize", r, [&] { return ParseRandomization(model, r); }));
  }
  spec.metrics = ParseMetrics(model, text.metrics);
  if (!text.shard.empty()) ParseShard(text.shard, &spec);
  ValidateRolloutSpec(model, spec);
  SayCtrlNoiseCentre(model, spec, notices);
  return spec;
}

SweepSpec ParseSweepSpec(const Model& model, SweepSpec spec, const BatchText& text,
                         const BatchWords& words, Notices* notices) {
  for (const std::string& v : text.vary) {
    spec.axes.push_back(NamedArgument("vary", v, [&] { return ParseSweepAxis(model, v); }));
    std::string subject = words.vary + " '" + v + "'";
    WarnAboutAxis(subject, spec.axes.back().prototype.warnings, notices);
    for (const Assignment& a : spec.axes.back().listed) WarnAboutAxis(subject, a.warnings, notices);
  }
  spec.metrics = ParseMetrics(model, text.metrics);
  ValidateSweepSpec(model, spec);
  return spec;
}

std::function<bool(const RolloutResult&)> InShard(const RolloutSpec& spec) {
  long index = spec.shard_index, count = spec.shard_count;
  return [index, count](const RolloutResult& r) { return r.index % count == index; };
}

BatchJob::BatchJob(const std::string& db, bool resume, const RunInfo& info, BatchWords words,
                   Notices* notices)
    : db_(db),
      unit_(info.kind == "rollout" ? "rollouts" : "cases"),
      words_(std::move(words)),
      notices_(notices),
      summary_(info.metrics.size()) {
  try {
    stored_ = OpenStoredRun(db, resume, info);
  } catch (const RunAlreadyStored& e) {
    throw ArgumentError(
        "store", Quoted(db),
        fmt::format("the results store already holds this run ({} run {}, {} of {} done); add "
                    "{} to complete it, or use another {} file.",
                    e.run().kind, e.run().id, e.done(), e.run().count, words_.resume,
                    words_.store));
  }
  if (stored_.fresh_start) {
    AddTo(notices_, {NoticeLevel::kNote, NoticeTopic::kBatch, words_.resume,
                     fmt::format("{} holds no {} run yet; starting one", Quoted(db), info.kind)});
  }
}

void BatchJob::Resume(long total, const std::function<bool(const RolloutResult&)>& mine,
                      const std::function<void(const RolloutResult&)>& row) {
  if (!stored_.store || stored_.done.empty()) return;
  stored_.store->ForEachResult(stored_.id, [&](const RolloutResult& r) {
    if (!mine(r)) return;
    ++summary_.resumed;
    summary_.Add(r);
    row(r);
  });
  if (summary_.resumed == 0) return;
  std::string text =
      summary_.resumed >= total
          ? fmt::format("all {} {} are stored in {}; nothing is left to run", total, unit_,
                        Quoted(db_))
          : fmt::format("{} of {} {} are stored in {}; running the rest", summary_.resumed, total,
                        unit_, Quoted(db_));
  AddTo(notices_, {NoticeLevel::kNote, NoticeTopic::kBatch, words_.resume, std::move(text)});
}

void BatchJob::Add(const RolloutResult& r) {
  ++summary_.run_now;
  summary_.Add(r);
  if (stored_.store) stored_.store->Add(stored_.id, r);
}

void BatchJob::Run(const std::function<void()>& work,
                   const std::function<std::string()>& finished) {
  auto start = std::chrono::steady_clock::now();
  try {
    work();
  } catch (const Interrupted& e) {
    // every row that finished is stored (the pool emits those past the first unfinished one)
    Commit();
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    throw Interrupted(StopMessage(e.what(), finished ? finished() : ""));
  }
  seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void BatchJob::Commit() {
  if (stored_.store) stored_.store->Commit();
}

std::string BatchJob::Finished() const {
  return fmt::format("{} {} finished", summary_.run_now, unit_);
}

std::string BatchJob::StopMessage(const std::string& stopped, const std::string& finished) const {
  return StoppedBatchMessage(stopped, finished.empty() ? Finished() : finished,
                             stored() ? db_ : "", words_.go_on);
}

void BatchJob::Complete(long total) { CompleteStoredRun(stored_, total); }

SweepNotices::SweepNotices(const SweepSpec& spec, Notices* notices, const Model* model)
    : spec_(spec), notices_(notices), effects_(spec, model) {}

void SweepNotices::See(const SweepCase& c, const RolloutResult& row) {
  ++cases_;
  effects_.See(row);
  for (std::size_t m = 0; m < c.metrics.size(); ++m) {
    if (c.metrics[m].ok) continue;
    ++failed_;
    auto [it, first] = problems_.try_emplace({m, c.metrics[m].problem}, 0L);
    ++it->second;
    if (!first) continue;
    AddTo(notices_, {NoticeLevel::kWarning, NoticeTopic::kBatch,
                     fmt::format("case {}, {}", c.index, spec_.metrics[m].text),
                     c.metrics[m].problem});
  }
}

std::vector<std::string> SweepNotices::Finish() {
  for (const auto& [key, cases] : problems_) {
    if (cases < 2) continue;
    AddTo(notices_, {NoticeLevel::kWarning, NoticeTopic::kBatch, spec_.metrics[key.first].text,
                     fmt::format("{} cases in all could not be measured because '{:.60}...'",
                                 cases, key.second)});
  }
  if (failed_ > 0) {
    long measurements = cases_ * static_cast<long>(spec_.metrics.size());
    AddTo(notices_, {NoticeLevel::kWarning, NoticeTopic::kBatch, "",
                     fmt::format("{} of {} measurements could not be made (see above)", failed_,
                                 measurements)});
  }
  std::vector<std::string> notes = effects_.Notes();
  for (const std::string& note : notes) {
    AddTo(notices_, {NoticeLevel::kNote, NoticeTopic::kBatch, "", note});
  }
  return notes;
}

}  // namespace plumb
