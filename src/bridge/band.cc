// The elastic band (band.h).

#include "bridge/band.h"

#include <fmt/format.h>

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
      "of robot); released {}",
      config.body, anchor_[0], anchor_[1], anchor_[2], distance, stiffness_, damping_, length_,
      stiffness_ * std::max(0.0, distance - length_), mass,
      release.empty() ? "never (no release_at or release_button)" : release);
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
  f[3] = f[4] = f[5] = 0;
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
