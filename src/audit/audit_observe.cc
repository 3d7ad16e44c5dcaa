// The runs the actuator, contact and behaviour layers judge: a run in pieces that goes on
// until the model is at rest, with the deepest contacts, solver effort and energy on the way
// and support and slip at the end.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "audit/audit_layers.h"
#include "audit/collision_graph.h"
#include "core/mujoco_compat.h"
#include "plumb/timing.h"

namespace plumb::audit {
namespace {

// Joins a piece of a run to the run so far. Pieces continue the data's clock, and Run numbers
// steps by that clock, so steps and first warnings already count from the run's start.
void Append(RunResult* total, const RunResult& part) {
  for (const WarningSummary& w : part.warnings) {
    auto same = std::find_if(total->warnings.begin(), total->warnings.end(),
                             [&](const WarningSummary& v) { return v.kind == w.kind; });
    if (same == total->warnings.end()) {
      total->warnings.push_back(w);
    } else {
      same->count += w.count;
      same->message = w.message;
    }
  }
  if (part.divergence) total->divergence = part.divergence;
  total->steps += part.steps;
  total->samples += part.samples;
  total->diverged = part.diverged;
}

// How deep a resting contact sinks by design: MuJoCo's contacts are soft, a spring-damper
// reference a_ref = -b v - k r with k = 1 / (dmax^2 timeconst^2 dampratio^2) for solref =
// (timeconst, dampratio), timeconst at least two timesteps (k = -solref[0] / dmax^2 for a
// direct stiffness), dmax = solimp[1]. Carrying gravity on that spring takes r = |g| / k: 3.5
// mm for the default solref (0.02, 1), as a Go2 foot at rest shows (3.8 mm). Penetration is
// judged against the larger of this and solimp's width, not only against the geoms' size: a
// foot 2 cm across sinking 4 mm is the model's softness, not a fault.
double SoftDepth(const mjModel* m, const mjContact& c) {
  double dmax = std::clamp(c.solimp[1], 0.0001, 0.9999);
  double k;
  if (c.solref[0] > 0) {
    double timeconst = c.solref[0];
    if (compat::ReferenceTimeconstClamped(m)) timeconst = std::max(timeconst, 2 * m->opt.timestep);
    double dampratio = c.solref[1] > 0 ? c.solref[1] : 1;
    k = 1 / (dmax * dmax * timeconst * timeconst * dampratio * dampratio);
  } else {
    k = -c.solref[0] / (dmax * dmax);
  }
  double g = GravityNorm(m);
  // solimp's width is the depth over which the designer let the impedance ramp up (Menagerie's
  // Spot feet: 36 mm): sinking within it is the contact working as designed
  return std::max(k > 0 && g > 0 ? g / k : 0.0, c.solimp[2]);
}

// A geom as a row names it; an unnamed one by its body too, which a reader can find.
std::string GeomLabel(const Model& model, int g) {
  std::string label = Elem(model, mjOBJ_GEOM, g, "geom");
  int b = model->geom_bodyid[g];
  if (!model.Name(mjOBJ_GEOM, g).empty() || b == 0) return label;
  return label + " of " + Elem(model, mjOBJ_BODY, b, "body");
}

std::string GeomPair(const Model& model, const mjContact& c) {
  return GeomLabel(model, c.geom1) + " / " + GeomLabel(model, c.geom2);
}

// After each step: energy, solver effort and the deepest contacts so far.
void TrackStep(const Model& work, const mjData* d, Observed* o) {
  const mjModel* m = work.get();
  double e = d->energy[0] + d->energy[1];
  o->energy_max = std::max(o->energy_max, e);
  o->energy_end = e;
  int iterations = compat::SolverIterations(d);
  o->max_iterations = std::max(o->max_iterations, iterations);
  if (d->nefc > 0 && iterations >= m->opt.iterations) ++o->steps_at_limit;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    double size = INFINITY;
    for (int g : {c.geom1, c.geom2}) {
      if (m->geom_type[g] != mjGEOM_PLANE && m->geom_type[g] != mjGEOM_HFIELD) {
        size = std::min(size, m->geom_rbound[g]);
      }
    }
    if (!std::isfinite(size) || size <= 0) continue;
    double depth = -c.dist / size;
    if (depth > o->deepest) {
      o->deepest = depth;
      o->deepest_m = -c.dist;
      o->deepest_soft = SoftDepth(m, c);
      o->deepest_pair = GeomPair(work, c);
    }
    if (depth > o->deepest_late) {
      o->deepest_late = depth;
      o->deepest_late_pair = GeomPair(work, c);
      o->deepest_late_m = -c.dist;
      o->deepest_late_soft = SoftDepth(m, c);
    }
  }
}

// The state at the end: at rest? supported? slipping?
void MeasureEnd(const Model& work, const mjData* d, Observed* o) {
  const mjModel* m = work.get();
  for (int i = 0; i < m->nv; ++i) {
    o->max_speed_end = std::max(o->max_speed_end, std::fabs(d->qvel[i]));
  }
  // what carries the free subtrees: the upward part of every contact force one of them gets
  // from anything outside it (the ground, a hand, jointed links, another free body: in a
  // stack, the lower body's extra load and the upper body's push cancel)
  double normal = 0;
  mjtNum up[3] = {0, 0, 1};
  if (GravityNorm(m) > 0) mju_scl3(up, m->opt.gravity, -1 / mju_norm3(m->opt.gravity));
  std::vector<mjtNum> jac1(3 * m->nv), jac2(3 * m->nv);
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    mjtNum force[6];
    mj_contactForce(m, d, i, force);
    int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
    if (m->body_rootid[b1] != m->body_rootid[b2]) {
      // the force on geom2's body, in the world frame (geom1's body gets its opposite)
      mjtNum world[3];
      mju_mulMatTVec(world, c.frame, force, 3, 3);
      double lift = mju_dot3(world, up);
      if (IsFreeRoot(m, m->body_rootid[b2])) normal += lift;
      if (IsFreeRoot(m, m->body_rootid[b1])) normal -= lift;
    }
    // relative velocity of the two bodies at the contact point, tangential part
    mj_jac(m, d, jac1.data(), nullptr, c.pos, b1);
    mj_jac(m, d, jac2.data(), nullptr, c.pos, b2);
    mjtNum v1[3], v2[3], rel[3];
    mju_mulMatVec(v1, jac1.data(), d->qvel, 3, m->nv);
    mju_mulMatVec(v2, jac2.data(), d->qvel, 3, m->nv);
    mju_sub3(rel, v1, v2);
    double along = mju_dot3(rel, c.frame);
    double slip = std::sqrt(std::max(0.0, mju_dot3(rel, rel) - along * along));
    if (c.friction[0] > 0 && slip > o->max_slip) {
      o->max_slip = slip;
      o->slip_pair = GeomPair(work, c);
    }
  }
  // weight of everything that floats freely (supported only by contacts)
  double floating = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] == 0 && m->body_jntnum[b] > 0 &&
        m->jnt_type[m->body_jntadr[b]] == mjJNT_FREE) {
      floating += m->body_subtreemass[b];
    }
  }
  double weight = floating * GravityNorm(m);
  if (weight > 0) o->support_ratio = normal / weight;
}

}  // namespace

Observed Observe(const Model& model, const std::vector<Assignment>& sets, const ReferencePose& ref,
                 double duration, const std::function<void(mjData*, double)>& control,
                 const AuditOptions& options, const std::string& label, double longest) {
  Observed o;
  o.label = label;
  Model work = model.Clone();
  work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  const mjModel* m = work.get();
  Data data(work);
  StartAtPose(work, data, ref, sets);
  o.energy0 = data->energy[0] + data->energy[1];
  long piece_steps = std::max(1L, std::lround(duration / m->opt.timestep / 4));
  long min_pieces = 4,
       max_pieces =
           std::max(4L, static_cast<long>(std::floor(longest / (piece_steps * m->opt.timestep))));
  RunSpec spec;
  spec.stop = options.stop;
  spec.until = piece_steps * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    if (control) control(d, d->time);
  };
  o.curves.resize(2);
  o.curves[0].quantity = "total energy (J)";
  o.curves[1].quantity = "fastest joint speed (rad/s or m/s)";
  for (AuditCurve& c : o.curves) c.label = label;
  spec.after_step = [&](const mjData* d, long) {
    TrackStep(work, d, &o);
    double speed = 0;
    for (int i = 0; i < m->nv; ++i) speed = std::max(speed, std::fabs(d->qvel[i]));
    for (AuditCurve& c : o.curves) c.t.push_back(d->time);
    o.curves[0].y.push_back(d->energy[0] + d->energy[1]);
    o.curves[1].y.push_back(speed);
  };
  NullSink sink;
  for (long piece = 0; piece < max_pieces; ++piece) {
    if (piece >= min_pieces) {
      double speed = 0;
      for (int i = 0; i < m->nv; ++i) speed = std::max(speed, std::fabs(data->qvel[i]));
      if (speed < kRestSpeed) break;
    }
    o.deepest_late = 0;  // only the last piece counts
    o.deepest_late_pair.clear();
    o.deepest_late_m = o.deepest_late_soft = 0;
    Append(&o.result, Run(work, data, spec, sink));
    if (o.result.diverged) break;
  }
  o.duration = o.result.steps * m->opt.timestep;
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  o.repro = KeepDiverged(work, o.result, options, label);
  if (!o.result.diverged) MeasureEnd(work, data.get(), &o);
  return o;
}

}  // namespace plumb::audit
