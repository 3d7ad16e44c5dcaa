// Audit layer 4, contacts: what each body can collide with, free bodies that fall forever,
// heavy bodies resting on light ones, and from the passive settle: penetration against the
// contacts' own softness, support, slip, solver effort and dropped contacts.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "audit/audit_layers.h"
#include "audit/collision_graph.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "contact";

// Per body: whether it can collide at all, and with what (visual-only geoms beside separate
// collision geoms, as in the Menagerie, are normal).
void CollidesWith(const Model& model, const CollisionGraph& graph, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  for (int b = 1; b < m->nbody; ++b) {
    std::vector<std::string> names;
    for (int p : graph.partners[b]) {
      names.push_back(p == 0 ? std::string("the world") : Elem(model, mjOBJ_BODY, p, "body"));
    }
    std::string with =
        names.empty() ? (graph.collides[b] ? "nothing: its contype/conaffinity meet no other geom's"
                                           : "nothing: visual geoms only, or no geoms")
        : names.size() <= 4
            ? fmt::format("{}", fmt::join(names, ", "))
            : fmt::format("{}, ... ({} bodies)", fmt::join(names.begin(), names.begin() + 3, ", "),
                          names.size());
    out->push_back(Make(L, "contact.collides_with", ElementOf(model, mjOBJ_BODY, b, "body"),
                        "collides with " + with, "", CheckStatus::kPass,
                        "which bodies this body's geoms can touch (contype/conaffinity, <pair>, "
                        "<exclude>, parent-child filter)"));
  }
}

// A free body that can touch nothing static, directly or through other bodies, falls
// forever (under gravity; <flag gravity="disable"/> means nothing falls); one that rests on
// the ground only through a much lighter free body loads that body's contacts far beyond
// their own weight.
void Grounding(const Model& model, const CollisionGraph& graph, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  for (int b = 1; b < m->nbody && GravityNorm(m) > 0; ++b) {
    if (m->body_parentid[b] != 0 || m->body_jntnum[b] == 0 ||
        m->jnt_type[m->body_jntadr[b]] != mjJNT_FREE) {
      continue;
    }
    if (!graph.grounded[b]) {
      // a robot description with no floor is meant to be included by a scene: a warning that
      // says so; a model with a floor that this body cannot reach is wrong
      bool fragment = !graph.static_collider;
      out->push_back(Make(
          L, "contact.free_fall", ElementOf(model, mjOBJ_BODY, b, "body"),
          fragment ? "nothing static in the model can collide (no floor)"
                   : "none of its geoms can reach a static geom through collisions",
          "a collision chain to the world", fragment ? CheckStatus::kWarn : CheckStatus::kFail,
          fragment ? "a free body under gravity with no floor falls forever: if this file is a "
                     "robot description that a scene includes (as Menagerie's robot.xml and "
                     "scene.xml), audit the scene; else add a floor"
                   : "a free body under gravity that collides with nothing static falls "
                     "forever: give one of its geoms contype/conaffinity that match the "
                     "floor's, or add a <contact><pair>"));
      continue;
    }
    // resting on the ground only through a much lighter free body: its contacts carry a
    // weight far beyond their own, the ill-conditioned case of MuJoCo's soft contacts
    int s = graph.support[b];
    double mass = m->body_subtreemass[b];
    if (s > 0 && graph.support_mass[b] > 0 && mass > 10 * graph.support_mass[b]) {
      out->push_back(WithNumbers(
          Make(L, "contact.heavy_on_light", ElementOf(model, mjOBJ_BODY, b, "body"),
               fmt::format("{:.3g} kg reaches the ground only through {} ({:.3g} kg)", mass,
                           Elem(model, mjOBJ_BODY, s, "body"), graph.support_mass[b]),
               "<= 10 x the lightest body on its way to the ground", CheckStatus::kWarn,
               "a heavy body that can rest only on a much lighter one loads that body's contacts "
               "far beyond its own weight: let the heavy body's geoms collide with the floor, or "
               "check the lighter body's mass"),
          {mass, "kg"}, {10 * graph.support_mass[b], "kg"}));
    }
  }
}

// How many times heavier than everything that carries it to the ground a body that collides
// with nothing may be before audit warns: a robot whose feet alone collide is 16 to 30 times
// its feet (G1, Go2); a 10 kg body on a 1e-6 kg pad is 1e7.
constexpr double kCarriedRatio = 100;

// In a free subtree (its weight reaches the ground only through contacts), a heavy body that
// collides with nothing rests on the colliding bodies it carries; when the heaviest of them
// (with what is welded to it) is far lighter, their few contacts hold a weight far beyond
// their own: the ill-conditioned case of soft contacts, and usually a geom that lost its
// contype (or a pad given a placeholder mass).
void CarriedByLighter(const Model& model, const CollisionGraph& graph, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  if (GravityNorm(m) <= 0) return;
  std::vector<double> group(m->nbody, 0.0);
  for (int b = 1; b < m->nbody; ++b) group[m->body_weldid[b]] += m->body_mass[b];
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_weldid[b] != b || !IsFreeRoot(m, m->body_rootid[b]) || group[b] <= 0) continue;
    // the weld group collides when any of its bodies does
    bool collides = false;
    for (int k = 1; k < m->nbody; ++k) {
      if (m->body_weldid[k] == b) collides = collides || !graph.partners[k].empty();
    }
    if (collides) continue;
    // the colliding weld groups below it, through joints
    int carrier = -1;
    for (int k = b + 1; k < m->nbody; ++k) {
      bool below = false;
      for (int p = k; p > 0; p = m->body_parentid[p]) below = below || p == b;
      if (!below || m->body_weldid[k] == b || graph.partners[k].empty()) continue;
      int g = m->body_weldid[k];
      if (carrier < 0 || group[g] > group[carrier]) carrier = g;
    }
    if (carrier < 0 || group[carrier] <= 0) continue;
    double ratio = group[b] / group[carrier];
    if (ratio <= kCarriedRatio) continue;
    out->push_back(WithNumbers(
        Make(L, "contact.carried", ElementOf(model, mjOBJ_BODY, b, "body"),
             fmt::format("{:.3g} kg collides with nothing; the heaviest body that collides below "
                         "it, {}, is {:.3g} kg: x{:.3g}",
                         group[b], Elem(model, mjOBJ_BODY, carrier, "body"), group[carrier], ratio),
             fmt::format("<= x{:g}", kCarriedRatio), CheckStatus::kWarn,
             "a heavy body that collides with nothing rests on much lighter ones, whose few "
             "contacts carry a weight far beyond their own: give its geoms contype/conaffinity "
             "(did a collision geom lose them?), or check the lighter body's mass"),
        {ratio, ""}, {kCarriedRatio, ""}));
  }
}

// Penetration judged at rest, once impacts are over (the last quarter-second piece of the
// settle); the peak during impacts alone is a warning, and so is a deep contact in a model
// still moving when the settle budget ran out. At rest, a contact deeper than a tenth of the
// smaller geom is judged against the depth its softness explains (SoftDepth): only a contact
// beyond 3x that is a warning, beyond 10x (and half the geom) a failure.
void Penetration(const Observed& settle, std::vector<CheckRow>* out) {
  bool at_rest = settle.max_speed_end < kRestSpeed;
  double late = settle.deepest_late;
  double soft = settle.deepest_late_soft;
  double excess = soft > 0 ? settle.deepest_late_m / soft : INFINITY;
  double impact_excess =
      settle.deepest_soft > 0 ? settle.deepest_m / settle.deepest_soft : INFINITY;
  CheckStatus status = late > 0.5 && at_rest && excess > 10 ? CheckStatus::kFail
                       : (late > 0.1 && excess > 3) || (settle.deepest > 0.5 && impact_excess > 10)
                           ? CheckStatus::kWarn
                           : CheckStatus::kPass;
  std::string measured =
      fmt::format("{:.3g} of the smaller geom's size at the end, {:.3g} at the worst impact", late,
                  settle.deepest);
  if (settle.deepest_late_m > 0 && soft > 0) {
    measured += fmt::format(
        "; {:.3g} mm deep at the end, {:.2g}x the {:.3g} mm its solref/solimp "
        "soften it by",
        1e3 * settle.deepest_late_m, excess, 1e3 * soft);
  }
  if (!at_rest) {
    measured += fmt::format("; did not settle in {:g} s (max |qvel| {:.3g} at the end)",
                            settle.duration, settle.max_speed_end);
  }
  // as numbers: the penetration at the end (a share of the smaller geom's size) against its
  // bound (0.5 when it fails, else 0.1), or the worst impact's against 0.5 when that alone
  // made the warning
  bool impact = status == CheckStatus::kWarn && !(late > 0.1 && excess > 3);
  Quantity depth{impact ? settle.deepest : late, ""};
  Quantity bound{impact || status == CheckStatus::kFail ? 0.5 : 0.1, ""};
  out->push_back(WithNumbers(
      Make(L, "contact.penetration", late > 0.1 ? settle.deepest_late_pair : settle.deepest_pair,
           measured,
           "<= 0.1 of the geom or <= 3x the soft-contact depth at the end (FAIL > 0.5 and > 10x at "
           "rest); <= 0.5 of the geom or <= 10x the soft depth at impacts",
           status,
           status == CheckStatus::kPass
               ? fmt::format("deepest contact penetration during a {:g} s settle", settle.duration)
           : at_rest
               ? "geoms sink deep into each other: stiffen solref (smaller time constant, at "
                 "least 2 timesteps), raise solimp, or shrink the timestep"
               : "geoms sink deep into each other while the model still moves: judge again at "
                 "rest (plumb run for longer), or stiffen solref / raise solimp"),
      depth, bound));
}

// At rest: do the contacts carry the free bodies' weight, and do resting contacts stick?
void SupportAndSlip(const Observed& settle, std::vector<CheckRow>* out) {
  bool at_rest = settle.max_speed_end < kRestSpeed;
  if (std::isfinite(settle.support_ratio) && at_rest) {
    double r = settle.support_ratio;
    bool carried = r > 0.9 && r < 1.1;
    // the bound of 0.9 .. 1.1 it crossed; none when inside
    Quantity crossed{carried ? NAN : r <= 0.9 ? 0.9 : 1.1, ""};
    out->push_back(WithNumbers(
        Make(L, "contact.support", "", fmt::format("contact normal force / weight = {:.3f}", r),
             "0.9 .. 1.1", carried ? CheckStatus::kPass : CheckStatus::kWarn,
             carried ? "at rest, the ground carries the free bodies' weight"
                     : "at rest but the contacts do not carry the weight: "
                       "check contact softness (solref/solimp) and "
                       "equality constraints"),
        {r, ""}, crossed));
    out->push_back(WithNumbers(
        Make(L, "contact.slip", settle.slip_pair, fmt::format("{:.3g} m/s", settle.max_slip),
             "<= 0.01 m/s", settle.max_slip <= 0.01 ? CheckStatus::kPass : CheckStatus::kWarn,
             settle.max_slip <= 0.01 ? "contacts that should stick do not slide at rest"
                                     : "a resting contact still slides: raise friction, use "
                                       "condim 4-6 or an elliptic cone, or more solver "
                                       "iterations"),
        {settle.max_slip, "m/s"}, {0.01, "m/s"}));
  } else if (!std::isnan(settle.support_ratio)) {
    out->push_back(Make(L, "contact.support", "",
                        fmt::format("did not settle in {:g} s: max |qvel| {:.3g} at the end",
                                    settle.duration, settle.max_speed_end),
                        fmt::format("< {:g} to judge", kRestSpeed), CheckStatus::kSkip,
                        "the model does not come to rest within the settle budget: support "
                        "and slip are judged only at rest"));
  }
}

// How often the constraint solver stops at its iteration limit.
void Solver(const mjModel* m, const Observed& settle, std::vector<CheckRow>* out) {
  bool any_contact =
      settle.deepest > 0 || !settle.deepest_pair.empty() || settle.max_iterations > 0;
  if (m->nv == 0 || (!any_contact && m->neq == 0)) return;
  double share = settle.result.steps > 0
                     ? static_cast<double>(settle.steps_at_limit) / settle.result.steps
                     : 0;
  // as numbers: the share of steps at the limit (a fraction, as its 10% bound)
  out->push_back(WithNumbers(
      Make(L, "contact.solver", "",
           fmt::format("max {} of {} iterations; at the limit in {:.0f}% of steps",
                       settle.max_iterations, m->opt.iterations, 100 * share),
           "at the limit in <= 10% of steps", share > 0.1 ? CheckStatus::kWarn : CheckStatus::kPass,
           share > 0.1 ? "the constraint solver often stops at its iteration "
                         "limit: raise <option iterations>, use the Newton solver, "
                         "or loosen tolerance"
                       : "the solver converges within its iteration limit"),
      {share, ""}, {0.1, ""}));
}

// Contacts or constraints dropped for want of room.
void Buffers(const Observed& settle, std::vector<CheckRow>* out) {
  for (const WarningSummary& w : settle.result.warnings) {
    if (w.kind == "CONTACTFULL" || w.kind == "CNSTRFULL") {
      out->push_back(
          WithNumbers(Make(L, "contact.buffer", "", fmt::format("{} x{}", w.kind, w.count), "0",
                           CheckStatus::kFail,
                           "contacts or constraints were dropped: raise <size nconmax/njmax> "
                           "(MuJoCo 2.x) or memory (3.x)"),
                      {static_cast<double>(w.count), ""}, {0, ""}));
    }
  }
}

}  // namespace

void ContactLayer(const Model& model, const Observed& settle, std::vector<CheckRow>* out) {
  CollisionGraph graph = MakeCollisionGraph(model.get());
  CollidesWith(model, graph, out);
  Grounding(model, graph, out);
  CarriedByLighter(model, graph, out);
  if (settle.result.diverged) {
    out->push_back(Make(L, "contact.settle", "", "the settle run diverged", "", CheckStatus::kFail,
                        DivergedFix(settle)));
    return;
  }
  Penetration(settle, out);
  SupportAndSlip(settle, out);
  Solver(model.get(), settle, out);
  Buffers(settle, out);
}

}  // namespace plumb::audit
