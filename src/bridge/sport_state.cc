// The sport-mode state (sport_state.h).

#include "bridge/sport_state.h"

#include <fmt/format.h>

#include <string>

#include "bridge/positions.h"
#include "core/joint_size.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb::bridge {
using internal::Echo;
using internal::FirstFreeBody;

namespace {

// A world-frame vector in the frame whose rotation matrix (row-major, to world) is `R`.
std::array<double, 3> ToLocal(const mjtNum* R, const double v[3]) {
  std::array<double, 3> out;
  for (int i = 0; i < 3; ++i) out[i] = R[i] * v[0] + R[3 + i] * v[1] + R[6 + i] * v[2];
  return out;
}

}  // namespace

SportState SportState::Bind(const Model& model, const BridgeSportState& config,
                            const BridgePositions& positions) {
  const mjModel* m = model.get();
  SportState s;
  if (!config.publish) return s;
  if (!config.base.empty()) {
    s.base_ = mj_name2id(m, mjOBJ_BODY, config.base.c_str());
    if (s.base_ <= 0) {
      throw ValueError(
          fmt::format("{}[sport_state] base = '{}': the model has no such body{}",
                      Place(positions, "sport_state.base"), Echo(config.base),
                      s.base_ == 0 ? " (the world body has no motion to report)" : ""));
    }
  } else {
    s.base_ = FirstFreeBody(m);
  }
  if (s.base_ < 0) return s;
  for (const std::string& name : config.feet) {
    std::string place = Place(positions, fmt::format("sport_state.feet[{}]", s.feet_.size()));
    Foot f;
    for (int type : {mjOBJ_SITE, mjOBJ_GEOM, mjOBJ_BODY}) {
      int id = mj_name2id(m, static_cast<mjtObj>(type), name.c_str());
      if (id < 0) continue;
      f.type = type;
      f.id = id;
      f.body = type == mjOBJ_SITE ? m->site_bodyid[id] : type == mjOBJ_GEOM ? -1 : id;
      break;
    }
    if (f.id < 0 || (f.type == mjOBJ_BODY && f.id == 0)) {
      throw ValueError(fmt::format(
          "{}[sport_state] feet: '{}' is not a site, geom or body of the model (name each foot's "
          "sole: a site or geom where it touches the ground, or its body)",
          place, Echo(name)));
    }
    s.feet_.push_back(f);
  }
  return s;
}

bool SportState::Touches(const Foot& foot, const mjModel* m, int geom) const {
  if (foot.type == mjOBJ_GEOM) return geom == foot.id;
  return m->geom_bodyid[geom] == foot.body;
}

SportReading SportState::Read(const mjModel* m, const mjData* d) const {
  SportReading r;
  if (base_ < 0) return r;
  const mjtNum* R = d->xmat + 9 * base_;
  const mjtNum* p = d->xpos + 3 * base_;
  mjtNum v[6];  // [angular; linear], world frame, at the body's origin (mjOBJ_XBODY)
  mj_objectVelocity(m, d, mjOBJ_XBODY, base_, v, 0);
  for (int k = 0; k < 3; ++k) {
    r.position[k] = p[k];
    r.velocity[k] = v[3 + k];
  }
  r.yaw_speed = v[2];
  std::array<double, 3> w = ToLocal(R, v);  // the base's angular velocity, its own frame
  double mean_z = 0;
  for (std::size_t i = 0; i < feet_.size(); ++i) {
    const Foot& f = feet_[i];
    const mjtNum* at = f.type == mjOBJ_SITE   ? d->site_xpos + 3 * f.id
                       : f.type == mjOBJ_GEOM ? d->geom_xpos + 3 * f.id
                                              : d->xpos + 3 * f.id;
    mjtNum fv[6];
    mj_objectVelocity(m, d, static_cast<mjtObj>(f.type == mjOBJ_BODY ? mjOBJ_XBODY : f.type), f.id,
                      fv, 0);
    double rel[3], rel_v[3];
    for (int k = 0; k < 3; ++k) {
      rel[k] = at[k] - p[k];
      rel_v[k] = fv[3 + k] - v[3 + k];
    }
    // d/dt of the position in the base's frame: R^T (v_foot - v_base) - w x p_local
    std::array<double, 3> local = ToLocal(R, rel), local_v = ToLocal(R, rel_v);
    r.foot_position[i] = local;
    r.foot_speed[i] = {local_v[0] - (w[1] * local[2] - w[2] * local[1]),
                       local_v[1] - (w[2] * local[0] - w[0] * local[2]),
                       local_v[2] - (w[0] * local[1] - w[1] * local[0])};
    mean_z += at[2] / static_cast<double>(feet_.size());
    for (int c = 0; c < d->ncon; ++c) {
      const mjContact& con = d->contact[c];
      if (con.efc_address < 0) continue;  // excluded, or beyond the margin: no force
      if (!Touches(f, m, con.geom1) && !Touches(f, m, con.geom2)) continue;
      mjtNum force[6];
      mj_contactForce(m, d, c, force);
      r.foot_force[i] += force[0];  // the normal force, in the contact's frame
    }
  }
  r.body_height = p[2] - (feet_.empty() ? 0.0 : mean_z);
  return r;
}

}  // namespace plumb::bridge
