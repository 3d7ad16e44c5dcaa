#include "plumb/keyframe.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>

#include "core/input_file.h"
#include "core/mujoco_compat.h"
#include "core/strings.h"
#include "plumb/check.h"
#include "plumb/error.h"

namespace plumb {

namespace {
std::string KeyLabel(const Model& model, int k) {
  std::string name = model.Name(mjOBJ_KEY, k);
  return name.empty() ? "#" + std::to_string(k) : name;
}

// What makes up a model's qpos: "a free joint (7: x y z, quaternion w x y z), 12 hinges".
std::string QposLayout(const mjModel* m) {
  int count[4] = {0, 0, 0, 0};  // free, ball, slide, hinge
  for (int j = 0; j < m->njnt; ++j) ++count[m->jnt_type[j]];
  const char* kinds[4][2] = {{"free joint (7: x y z, quaternion w x y z)", "free joints (7 each)"},
                             {"ball joint (4: quaternion)", "ball joints (4 each)"},
                             {"slide", "slides"},
                             {"hinge", "hinges"}};
  std::vector<std::string> parts;
  for (int t = 0; t < 4; ++t) {
    if (count[t] == 0) continue;
    parts.push_back((count[t] == 1 ? "a " : std::to_string(count[t]) + " ") +
                    kinds[t][count[t] == 1 ? 0 : 1]);
  }
  return internal::Join(parts, ", ");
}

// The numbers of `text`, separated by commas or white space.
std::vector<std::string> Numbers(const std::string& text) {
  std::vector<std::string> out(1);
  for (char c : text) {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!out.back().empty()) out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  if (out.back().empty()) out.pop_back();
  return out;
}
// Joint j at position `q` (qpos of its qposadr) when that lies outside its range by more than
// 1e-6 of the range's width: hinges, slides and ball joints (by their rotation angle).
std::optional<StartIssue> JointOutside(const Model& model, int j, const mjtNum* q) {
  const mjModel* m = model.get();
  int type = m->jnt_type[j];
  if (!m->jnt_limited[j] || type == mjJNT_FREE) return std::nullopt;
  double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
  if (!(hi > lo)) return std::nullopt;  // an empty range is structure.joint_range's finding
  double value = q[0];
  if (type == mjJNT_BALL) {
    // a ball joint's range bounds its rotation angle: [0, hi]
    value = 2 * std::acos(std::min(1.0, std::fabs(q[0])));
    lo = 0;
  }
  double slack = 1e-6 * (hi - lo);
  if (value >= lo - slack && value <= hi + slack) return std::nullopt;
  StartIssue issue;
  issue.kind = StartIssue::Kind::kJointOutsideRange;
  issue.id = j;
  issue.element = ElementLabel({"joint", model.Name(mjOBJ_JOINT, j), j});
  issue.unit = type == mjJNT_SLIDE ? "m" : "rad";
  issue.value = value;
  issue.lo = lo;
  issue.hi = hi;
  bool below = value < lo;
  issue.text =
      fmt::format("{} starts at {:.4g} {}, outside its range [{:.4g}, {:.4g}] ({:.3g} {} {} it)",
                  issue.element, value, issue.unit, lo, hi, below ? lo - value : value - hi,
                  issue.unit, below ? "below" : "above");
  return issue;
}

// For each hinge or slide that qpos0 puts outside its range: the issue, and the assignment that
// moves it 1% of the range's width inside its nearest bound.
void IntoRange(const Model& model, ReferencePose* pose) {
  const mjModel* m = model.get();
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    int adr = m->jnt_qposadr[j];
    std::optional<StartIssue> issue = JointOutside(model, j, m->qpos0 + adr);
    if (!issue) continue;
    double width = issue->hi - issue->lo;
    double inside = issue->value < issue->lo ? issue->lo + 0.01 * width : issue->hi - 0.01 * width;
    std::string name = model.Name(mjOBJ_JOINT, j);
    std::string path = name.empty() ? fmt::format("qpos[{}]", adr) : "qpos[" + name + "]";
    pose->into_range.push_back(ParseAssignment(model, fmt::format("{}={:.17g}", path, inside)));
    pose->into_range.back().text = fmt::format("{}={:.5g}", path, inside);
    pose->outside.push_back(std::move(*issue));
  }
}

}  // namespace

int FindKeyframe(const Model& model, const std::string& name) {
  const mjModel* m = model.get();
  std::vector<std::string> names;
  for (int k = 0; k < m->nkey; ++k) {
    names.push_back(KeyLabel(model, k));
    if (names.back() == name) return k;
  }
  // a named keyframe by its id too ("#1"; Python's keyframe=1): names first, as cameras
  if (name.size() > 1 && name[0] == '#' &&
      name.find_first_not_of("0123456789", 1) == std::string::npos && name.size() < 10) {
    int k = std::stoi(name.substr(1));
    if (k < m->nkey) return k;
  }
  if (names.empty()) {
    throw ArgumentError(
        "keyframe", Quoted(name),
        "the model '" + model.file() +
            "' has no keyframes (MJCF <keyframe><key name=... qpos=.../></keyframe>). "
            "Set the start state with assignments (qpos[...]=...) instead.");
  }
  std::string hint = internal::DidYouMean(name, names);
  throw ArgumentError("keyframe", Quoted(name),
                      "no such keyframe in '" + model.file() + "'. Its keyframes: " +
                          internal::Join(names, ", ") + "." + (hint.empty() ? "" : " " + hint));
}

std::vector<Assignment> KeyframeAssignments(const Model& model, const std::string& name) {
  if (name.empty()) return {};
  const mjModel* m = model.get();
  int k = FindKeyframe(model, name);
  std::string label = "keyframe '" + KeyLabel(model, k) + "': ";
  std::vector<Assignment> out;
  auto add = [&](const char* field, const mjtNum* source, long n) {
    if (n == 0) return;
    Assignment a;
    a.text = label + field;
    a.path = ResolvePath(model, field);
    a.values.assign(source + k * n, source + (k + 1) * n);
    out.push_back(std::move(a));
  };
  add("time", m->key_time, 1);
  add("qpos", m->key_qpos, m->nq);
  add("qvel", m->key_qvel, m->nv);
  add("act", m->key_act, m->na);
  add("ctrl", m->key_ctrl, m->nu);
  add("mocap_pos", m->key_mpos, 3L * m->nmocap);
  add("mocap_quat", m->key_mquat, 4L * m->nmocap);
  auto [plastic, nplastic] = compat::KeyPlastic(m);
  if (plastic) add("plastic", plastic, nplastic);
  return out;
}

ReferencePose FindReferencePose(const Model& model, const std::string& named) {
  ReferencePose pose;
  if (!named.empty()) {
    pose.keyframe = FindKeyframe(model, named);
    pose.description = "keyframe '" + named + "' (named by the caller)";
    return pose;
  }
  for (const char* name : {"home", "test"}) {
    int k = mj_name2id(model.get(), mjOBJ_KEY, name);
    if (k >= 0) {
      pose.keyframe = k;
      pose.description = std::string("keyframe '") + name + "'";
      return pose;
    }
  }
  pose.description = "qpos0";
  IntoRange(model, &pose);
  if (!pose.into_range.empty()) {
    pose.description += fmt::format(" ({} joint{} brought into {} range{})", pose.into_range.size(),
                                    pose.into_range.size() == 1 ? "" : "s",
                                    pose.into_range.size() == 1 ? "its" : "their",
                                    pose.into_range.size() == 1 ? "" : "s");
  }
  return pose;
}

std::vector<Assignment> ReferenceStart(const Model& model, const ReferencePose& pose,
                                       const std::vector<Assignment>& sets) {
  std::vector<Assignment> start = pose.into_range;
  if (pose.keyframe >= 0) start = KeyframeAssignments(model, KeyLabel(model, pose.keyframe));
  start.insert(start.end(), sets.begin(), sets.end());
  return start;
}

std::string DescribeStart(const ReferencePose& pose, const std::vector<Assignment>& sets) {
  if (sets.empty()) return pose.description;
  std::vector<std::string> texts;
  std::size_t length = 0;
  for (const Assignment& a : sets) {
    texts.push_back(a.text);
    length += a.text.size();
  }
  if (texts.size() <= 3 && length <= 60)
    return pose.description + " with " + internal::Join(texts, ", ");
  return fmt::format("{} with {} assignment{}", pose.description, texts.size(),
                     texts.size() == 1 ? "" : "s");
}

void StartAtPose(Model& model, Data& data, const ReferencePose& pose,
                 const std::vector<Assignment>& sets) {
  if (pose.keyframe < 0) {
    ApplyAssignments(model, data, ReferenceStart(model, pose, sets));
    return;
  }
  ApplyAssignments(model, data, sets);
  mj_resetDataKeyframe(model.get(), data.get(), pose.keyframe);
  WriteState(model, data, sets);
  data.Forward();
}

Assignment QposAssignment(const Model& model, const std::string& values) {
  const mjModel* m = model.get();
  std::vector<std::string> numbers = Numbers(values);
  if (static_cast<int>(numbers.size()) != m->nq) {
    throw ArgumentError("qpos", Quoted(values),
                        std::to_string(numbers.size()) + " values, but '" + model.file() +
                            "' has nq = " + std::to_string(m->nq) + " (" + QposLayout(m) +
                            "): give all " + std::to_string(m->nq) +
                            " in qpos order, separated by commas or spaces.");
  }
  try {
    return ParseAssignment(model, "qpos=" + internal::Join(numbers, ","));
  } catch (const ArgumentError& e) {
    throw ArgumentError("qpos", Quoted(values), e.problem());
  }
}

std::vector<Assignment> PoseFileAssignments(const Model& model, const std::string& path) {
  std::istringstream in(internal::ReadInputFile(path, internal::InputKind::kPoseFile));
  std::vector<std::pair<int, std::string>> lines;  // line number, text
  bool assignments = false;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::size_t last = line.find_last_not_of(" \t\r");
    lines.emplace_back(number, line.substr(first, last - first + 1));
    assignments = assignments || line.find('=') != std::string::npos;
  }
  auto where = [&](int number) { return Quoted(path + ":" + std::to_string(number)); };
  if (!assignments) {
    // a bare qpos vector, over one line or several
    std::string values;
    for (const auto& entry : lines) values += entry.second + " ";
    try {
      return {QposAssignment(model, values)};
    } catch (const ArgumentError& e) {
      throw ArgumentError("pose", Quoted(path), e.problem());
    }
  }
  std::vector<Assignment> out;
  for (const auto& [number, text] : lines) {
    try {
      out.push_back(ParseAssignment(model, text));
    } catch (const ArgumentError& e) {
      throw ArgumentError("pose", where(number), e.value() + ": " + e.problem());
    } catch (const Error& e) {
      throw ArgumentError("pose", where(number), e.what());
    }
  }
  return out;
}

std::vector<Assignment> StartAssignments(const Model& model, const StartSpec& start,
                                         Notices* notices, const std::string& prefix) {
  std::vector<Assignment> out = KeyframeAssignments(model, start.keyframe);
  auto add = [&](const char* argument, Assignment a) {
    AddAssignmentNotices(a, prefix + argument, notices);
    out.push_back(std::move(a));
  };
  if (!start.pose.empty()) {
    for (Assignment& a : PoseFileAssignments(model, start.pose)) add("pose", std::move(a));
  }
  if (!start.qpos.empty()) add("qpos", QposAssignment(model, start.qpos));
  for (const std::string& text : start.sets) add("set", ParseAssignment(model, text));
  return out;
}

void AddAssignmentNotices(const Assignment& a, const std::string& argument, Notices* notices) {
  for (const std::string& w : a.warnings) {
    AddTo(notices, {NoticeLevel::kWarning, NoticeTopic::kStart, argument + " '" + a.text + "'", w});
  }
}

namespace {
std::string GeomNamed(const Model& model, int g) {
  std::string name = model.Name(mjOBJ_GEOM, g);
  if (!name.empty()) return fmt::format("'{}' (id {})", name, g);
  std::string body = model.Name(mjOBJ_BODY, model->geom_bodyid[g]);
  return body.empty() ? fmt::format("#{}", g) : fmt::format("#{} of body '{}'", g, body);
}
}  // namespace

std::vector<StartIssue> StartIssues(const Model& model, const Data& data) {
  const mjModel* m = model.get();
  const mjData* d = data.get();
  std::vector<StartIssue> out;
  for (int j = 0; j < m->njnt; ++j) {
    std::optional<StartIssue> issue = JointOutside(model, j, d->qpos + m->jnt_qposadr[j]);
    if (issue) out.push_back(std::move(*issue));
  }
  std::vector<StartIssue> contacts;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& con = d->contact[c];
    double depth = -con.dist;
    double width = con.solimp[2];
    if (con.exclude != 0 || !(depth > width)) continue;
    // one issue per geom pair: its deepest contact
    auto same = std::find_if(contacts.begin(), contacts.end(), [&](const StartIssue& other) {
      return other.id == con.geom1 && other.id2 == con.geom2;
    });
    if (same != contacts.end()) {
      if (depth > same->value)
        contacts.erase(same);
      else
        continue;
    }
    StartIssue issue;
    issue.kind = StartIssue::Kind::kDeepContact;
    issue.id = con.geom1;
    issue.id2 = con.geom2;
    issue.element = "geoms " + GeomNamed(model, issue.id) + " and " + GeomNamed(model, issue.id2);
    issue.unit = "m";
    issue.value = depth;
    issue.hi = width;
    issue.text = fmt::format(
        "{} start {:.3g} mm into each other, deeper than the pair's solimp "
        "width {:.3g} mm",
        issue.element, 1e3 * depth, 1e3 * width);
    contacts.push_back(std::move(issue));
  }
  std::sort(contacts.begin(), contacts.end(),
            [](const StartIssue& a, const StartIssue& b) { return a.value > b.value; });
  out.insert(out.end(), contacts.begin(), contacts.end());
  return out;
}

std::vector<StartIssue> MovedIntoRange(const Model& model, const Data& data,
                                       const ReferencePose& pose) {
  std::vector<StartIssue> out;
  for (std::size_t i = 0; i < pose.outside.size() && i < pose.into_range.size(); ++i) {
    const StartIssue& issue = pose.outside[i];
    if (data->qpos[model->jnt_qposadr[issue.id]] == pose.into_range[i].values[0]) {
      out.push_back(issue);
    }
  }
  return out;
}

std::string DescribeStartIssues(const std::vector<StartIssue>& issues, int listed) {
  std::vector<std::string> parts;
  for (const StartIssue& issue : issues) {
    if (static_cast<int>(parts.size()) == listed) break;
    if (issue.kind == StartIssue::Kind::kJointOutsideRange) {
      parts.push_back(fmt::format("{} at {:.4g} {} outside [{:.4g}, {:.4g}]", issue.element,
                                  issue.value, issue.unit, issue.lo, issue.hi));
    } else {
      parts.push_back(fmt::format("{} {:.3g} mm deep (solimp width {:.3g} mm)", issue.element,
                                  1e3 * issue.value, 1e3 * issue.hi));
    }
  }
  std::string text = internal::Join(parts, "; ");
  int more = static_cast<int>(issues.size()) - static_cast<int>(parts.size());
  if (more > 0) text += fmt::format("; {} more", more);
  return text;
}

}  // namespace plumb
