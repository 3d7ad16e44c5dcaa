// What the audit's layers share: how a finding names an element, the reference pose, the
// cost budget of a run and what a diverged run's finding says.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "check/audit_layers.h"
#include "core/geometry.h"

namespace plumb::audit {

Element ElementOf(const Model& model, int obj, int id, const char* noun) {
  Element e;
  e.type = noun;
  e.name = model.Name(obj, id);
  e.id = id;
  e.text = e.name.empty() ? fmt::format("{} #{}", noun, id)
                          : fmt::format("{} '{}' (id {})", noun, e.name, id);
  return e;
}

std::string Elem(const Model& model, int obj, int id, const char* noun) {
  return ElementOf(model, obj, id, noun).text;
}

Finding Make(const char* layer, std::string check, const Element& element, std::string measured,
             std::string threshold, CheckStatus status, std::string fix) {
  Finding f = Make(layer, std::move(check), element.text, std::move(measured), std::move(threshold),
                   status, std::move(fix));
  f.element_type = element.type;
  f.element_name = element.name;
  f.element_id = element.id;
  return f;
}

Finding Make(const char* layer, std::string check, std::string element, std::string measured,
             std::string threshold, CheckStatus status, std::string fix) {
  Finding f;
  f.layer = layer;
  f.check = std::move(check);
  f.element = std::move(element);
  f.measured = std::move(measured);
  f.threshold = std::move(threshold);
  f.status = status;
  f.fix = std::move(fix);
  return f;
}

void ListedNote(const char* layer, const char* check, const char* noun, int total,
                std::vector<Finding>* out, int shown) {
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

}  // namespace plumb::audit
