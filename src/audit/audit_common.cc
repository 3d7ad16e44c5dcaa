// What the audit's layers share: how a finding names an element, the reference pose, the
// cost budget of a run and what a diverged run's finding says.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "audit/audit_layers.h"
#include "core/geometry.h"
#include "plumb/describe.h"

namespace plumb::audit {
using internal::PrimitiveVolume;

CheckElement ElementOf(const Model& model, int obj, int id, const char* noun) {
  return CheckElement{noun, model.Name(obj, id), id};
}

int DrivenJoint(const mjModel* m, int u) {
  int trn = m->actuator_trntype[u];
  return trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT ? m->actuator_trnid[2 * u] : -1;
}

std::string Elem(const Model& model, int obj, int id, const char* noun) {
  return ElementLabel(ElementOf(model, obj, id, noun));
}

CheckRow Make(const char* layer, std::string check, const CheckElement& element,
              std::string measured, std::string threshold, CheckStatus status, std::string fix) {
  CheckRow row = Make(layer, std::move(check), std::string(), std::move(measured),
                      std::move(threshold), status, std::move(fix));
  row.element = element;
  return row;
}

CheckRow Make(const char* layer, std::string check, std::string subject, std::string measured,
              std::string threshold, CheckStatus status, std::string fix) {
  CheckRow row;
  row.section = layer;
  row.id = std::move(check);
  row.subject = std::move(subject);
  row.measured_text = std::move(measured);
  row.reference_text = std::move(threshold);
  row.threshold = !row.reference_text.empty();
  row.status = status;
  bool finding = status == CheckStatus::kWarn || status == CheckStatus::kFail;
  (finding ? row.fix : row.explanation) = std::move(fix);
  return row;
}

CheckRow WithNumbers(CheckRow row, Quantity measured, Quantity reference) {
  row.measured = std::move(measured);
  row.reference = std::move(reference);
  return row;
}

void ListedNote(const char* layer, const char* check, const char* noun, int total,
                std::vector<CheckRow>* out, int shown) {
  if (total <= shown) return;
  out->push_back(
      Make(layer, check, "", fmt::format("{} of {} {} listed", shown, total, noun), "",
           CheckStatus::kPass,
           fmt::format("only {} rows are shown; plumb inspect lists every element", shown)));
}

double GravityNorm(const mjModel* m) {
  return (m->opt.disableflags & mjDSBL_GRAVITY) ? 0 : mju_norm3(m->opt.gravity);
}

bool Moves(const mjModel* m, int b) { return b > 0 && m->body_weldid[b] != 0; }

double GeomVolume(const mjModel* m, int g) {
  return PrimitiveVolume(m->geom_type[g], m->geom_size + 3 * g);
}

double Duration(const mjModel* m, double wanted, double budget) {
  double steps = std::max(20.0, std::min(wanted / m->opt.timestep,
                                         budget / std::max(30.0, static_cast<double>(m->nv))));
  return std::ceil(steps) * m->opt.timestep;
}

std::string KeepDiverged(const Model& work, const RunResult& run, const AuditOptions& options,
                         const std::string& label) {
  if (!run.diverged || !options.keep_diverged) return "";
  return options.keep_diverged(work, run, "the audit run that diverged: " + label);
}

std::string DivergedFix(const Observed& o) {
  return o.result.divergence->reason +
         " Fix: a smaller timestep (or the implicit integrator), joint damping or armature "
         "on the named joint, softer contacts or gains; plumb converge shows whether the "
         "timestep is the cause." +
         (o.repro.empty() ? "" : " Repro folder: " + o.repro + ".");
}

void DelayRows(const Model& model, const std::string& kind, const char* layer, const char* check,
               std::vector<CheckRow>* out) {
  const int obj = kind == "actuator" ? mjOBJ_ACTUATOR : mjOBJ_SENSOR;
  for (const DelayDescription& d : Delays(model)) {
    if (d.kind != kind) continue;
    std::string measured = fmt::format("delay {:g} s, buffer {} x {:g} s = {:g} s", d.delay,
                                       d.nsample, model->opt.timestep, d.buffer);
    out->push_back(WithNumbers(
        Make(layer, check, ElementOf(model, obj, d.id, kind.c_str()), measured, "delay <= buffer",
             d.shortened() ? CheckStatus::kWarn : CheckStatus::kPass,
             d.shortened()
                 ? fmt::format("MuJoCo keeps {} samples, so it delays by {:g} s, not {:g} s: set "
                               "nsample=\"{}\" or more",
                               d.nsample, d.buffer, d.delay, d.needed_nsample)
                 : "the history buffer holds the whole delay"),
        {d.delay, "s"}, {d.buffer, "s"}));
  }
}

}  // namespace plumb::audit
