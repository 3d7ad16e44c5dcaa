// The elastic band (band.h).

#include "bridge/band.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bridge/gamepad_script.h"
#include "bridge/positions.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb::bridge {

Band::Band(const mjModel* m, const mjData* d, const BridgeBand& config,
           const BridgePositions& positions) {
  if (config.body.empty()) return;
  body_ = mj_name2id(m, mjOBJ_BODY, config.body.c_str());
  if (body_ <= 0) {
    throw ValueError(fmt::format("{}[band] body = '{}': the model has no such body{}",
                                 Place(positions, "band.body"), internal::Echo(config.body),
                                 body_ == 0 ? " (the world body cannot hang on a band)" : ""));
  }
  const mjtNum* com = d->xipos + 3 * body_;
  for (int k = 0; k < 3; ++k) {
    anchor_[k] = std::isnan(config.anchor[k]) ? com[k] + (k == 2 ? 1.0 : 0.0) : config.anchor[k];
  }
  stiffness_ = config.stiffness;
  damping_ = config.damping;
  double distance = std::sqrt(mju_dist3(anchor_, com) * mju_dist3(anchor_, com));
  // the mass the band carries: the whole tree the body belongs to
  double mass = m->body_subtreemass[m->body_rootid[body_]];
  double g = mju_norm3(m->opt.gravity);
  length_ = config.length;
  if (std::isnan(length_)) {
    length_ = stiffness_ > 0 ? std::max(0.0, distance - mass * g / stiffness_) : distance;
  }
  SetHold(m, d, config);
  release_at_ = config.release_at;
  if (!config.release_button.empty()) {
    button_ = ButtonBit(config.release_button);
    button_name_ = kButtonNames[button_];
  }
  std::string release;
  if (std::isfinite(release_at_)) release = fmt::format("at t = {:g} s", release_at_);
  if (button_ >= 0) {
    release += fmt::format("{}on the gamepad's {}", release.empty() ? "" : " or ", button_name_);
  }
  description_ = fmt::format(
      "band: {} hangs from ({:.3g}, {:.3g}, {:.3g}), {:.3g} m above its centre of mass, on "
      "k = {:g} N/m, c = {:g} N*s/m, rest length {:.3g} m (a pull of {:.1f} N now, for {:.1f} kg "
      "of robot), {}; released {}",
      config.body, anchor_[0], anchor_[1], anchor_[2], distance, stiffness_, damping_, length_,
      stiffness_ * std::max(0.0, distance - length_), mass,
      hold_stiffness_ > 0 ? fmt::format("held upright at its start orientation (k = {:.4g} "
                                        "N*m/rad, c = {:.4g} N*m*s/rad)",
                                        hold_stiffness_, hold_damping_)
                          : std::string("free to turn (hold_stiffness = 0)"),
      release.empty() ? "never (no release_at or release_button)" : release);
}

namespace {

// The robot's rotational inertia about the body's centre of mass (a scalar: the largest it
// can be, each body's mass at its distance plus the trace of its own inertia), kg*m^2.
double TreeInertia(const mjModel* m, const mjData* d, int body) {
  int root = m->body_rootid[body];
  const mjtNum* c = d->xipos + 3 * body;
  double inertia = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_rootid[b] != root) continue;
    double r2 = 0;
    for (int k = 0; k < 3; ++k) r2 += (d->xipos[3 * b + k] - c[k]) * (d->xipos[3 * b + k] - c[k]);
    const mjtNum* i = m->body_inertia + 3 * b;
    inertia += m->body_mass[b] * r2 + 0.5 * (i[0] + i[1] + i[2]);
  }
  return inertia;
}

}  // namespace

// The hold pulls through xfrc_applied, which MuJoCo integrates explicitly: its defaults stay
// within what one step of the body alone can take (its smallest principal inertia I: a
// stiffness of at most I / (2 dt)^2 and a damping of at most I / (2 dt), a quarter and a half
// of the explicit limits), as the joints that tie it to the robot may be soft.
void Band::SetHold(const mjModel* m, const mjData* d, const BridgeBand& config) {
  double mass = m->body_subtreemass[m->body_rootid[body_]];
  double weight = mass * mju_norm3(m->opt.gravity);
  const mjtNum* own = m->body_inertia + 3 * body_;
  double least = std::min({own[0], own[1], own[2]});
  double dt = m->opt.timestep;
  hold_stiffness_ = std::isnan(config.hold_stiffness)
                        ? std::min(10 * weight * 1.0, least / (4 * dt * dt))
                        : config.hold_stiffness;
  hold_damping_ =
      std::isnan(config.hold_damping)
          ? std::min(2 * std::sqrt(hold_stiffness_ * TreeInertia(m, d, body_)), least / (2 * dt))
          : config.hold_damping;
  mju_copy4(start_quat_, d->xquat + 4 * body_);
}

void Band::Apply(const mjModel* m, mjData* d) const {
  if (!on()) return;
  const mjtNum* com = d->xipos + 3 * body_;
  double line[3];
  mju_sub3(line, anchor_, com);
  double distance = mju_normalize3(line);
  mjtNum v[6];  // [angular; linear] at the centre of mass (mjOBJ_BODY), world frame
  mj_objectVelocity(m, d, mjOBJ_BODY, body_, v, 0);
  double speed = mju_dot3(v + 3, line);  // how fast the body moves toward the anchor
  double stretch = distance - length_;
  // a band pulls, never pushes: slack, it carries no force (its damper neither)
  double pull = stretch > 0 ? std::max(0.0, stiffness_ * stretch + damping_ * -speed) : 0.0;
  mjtNum* f = d->xfrc_applied + 6 * body_;
  for (int k = 0; k < 3; ++k) f[k] = pull * line[k];
  // the hold: a torque toward the start orientation, against the turning (world frame)
  mjtNum back[4], turn[3];
  mju_negQuat(back, d->xquat + 4 * body_);
  mjtNum error[4];
  mju_mulQuat(error, start_quat_, back);  // from now to the start, in the world frame
  mju_quat2Vel(turn, error, 1);           // its axis times its angle, rad
  for (int k = 0; k < 3; ++k) f[3 + k] = hold_stiffness_ * turn[k] - hold_damping_ * v[k];
}

std::string Band::Release(mjData* d, std::uint16_t keys) {
  if (!on()) return "";
  bool by_time = d->time >= release_at_ - 1e-12;
  bool by_button = button_ >= 0 && (keys >> button_ & 1u);
  if (!by_time && !by_button) return "";
  released_ = true;
  mju_zero(d->xfrc_applied + 6 * body_, 6);
  return fmt::format("band: released at t = {:.6g} s ({})", d->time,
                     by_time ? "release_at" : "the gamepad's " + button_name_);
}

}  // namespace plumb::bridge
