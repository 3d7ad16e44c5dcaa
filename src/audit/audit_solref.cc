// structure.solref_clamp: constraints whose written solref time constant MuJoCo raises to two
// timesteps (its refsafe safety limit), so the model runs softer than it says.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"
#include "core/solref.h"
#include "plumb/error.h"

namespace plumb::audit {

namespace {

constexpr const char* L = "structure";
constexpr const char* kCheck = "structure.solref_clamp";
constexpr int kNamesShown = 12;  // elements a row names before "and N more"

// How a solref array's rows read in a row: the element kind, what constraint they make, the
// MJCF attribute that sets them, and which of the kind's SolrefClass time constants is theirs.
struct ArrayKind {
  const char* array;
  int obj;
  const char* noun;        // "joint"
  const char* plural;      // "joints"
  const char* constraint;  // "limits"
  const char* attribute;   // "solreflimit"
  int class_index;
};

constexpr ArrayKind kKinds[] = {
    {"geom_solref", mjOBJ_GEOM, "geom", "geoms", "contacts", "solref", 0},
    {"pair_solref", mjOBJ_PAIR, "pair", "pairs", "contacts", "solref", 0},
    {"pair_solreffriction", mjOBJ_PAIR, "pair", "pairs", "contact friction, elliptic cone",
     "solreffriction", 1},
    {"flex_solref", compat::kObjFlex, "flex", "flexes", "contacts", "solref", 0},
    {"opt.o_solref", -1, "option", "options", "every contact, under the override flag",
     "o_solref", 0},
    {"jnt_solref", mjOBJ_JOINT, "joint", "joints", "limits", "solreflimit", 0},
    {"dof_solref", mjOBJ_JOINT, "joint", "joints", "friction loss", "solreffriction", 1},
    {"tendon_solref_lim", mjOBJ_TENDON, "tendon", "tendons", "limits", "solreflimit", 0},
    {"tendon_solref_fri", mjOBJ_TENDON, "tendon", "tendons", "friction loss", "solreffriction",
     1},
    {"eq_solref", mjOBJ_EQUALITY, "equality", "equalities", "equality constraint", "solref", 0},
};

const ArrayKind* KindOf(const std::string& array) {
  for (const ArrayKind& k : kKinds) {
    if (array == k.array) return &k;
  }
  return nullptr;
}

// The classes of the elements of `kind`, when the MJCF is at hand (mjSpec); nullptr otherwise.
const std::vector<compat::SolrefClass>* ClassesOf(const compat::SolrefClasses* classes,
                                                  const ArrayKind& kind) {
  if (classes == nullptr) return nullptr;
  switch (kind.obj) {
    case mjOBJ_GEOM: return &classes->geom;
    case mjOBJ_PAIR: return &classes->pair;
    case mjOBJ_JOINT: return &classes->joint;
    case mjOBJ_TENDON: return &classes->tendon;
    case mjOBJ_EQUALITY: return &classes->equality;
    default: return nullptr;
  }
}

// Where element `id`'s time constant `timeconst` comes from: "default class 'x'" when its class
// gives that value, "MuJoCo's default" for the built-in 0.02 s, "" when written on the element
// (or unknown).
std::string Source(const compat::SolrefClasses* classes, const ArrayKind& kind, int id,
                   double timeconst) {
  const std::vector<compat::SolrefClass>* list = ClassesOf(classes, kind);
  if (list == nullptr || id < 0 || id >= static_cast<int>(list->size())) return "";
  const compat::SolrefClass& c = (*list)[id];
  if (c.name.empty() || c.timeconst[kind.class_index] != timeconst) return "";
  if (c.name == "main" && timeconst == 0.02) return "MuJoCo's default";
  return fmt::format("default class '{}'", c.name);
}

// An element as a grouped row lists it: 'name', or #id (of body 'b' for an unnamed geom).
std::string Listed(const Model& model, const ArrayKind& kind, int id) {
  if (kind.obj < 0) return "'o_solref'";
  std::string name = model.Name(kind.obj, id);
  if (!name.empty()) return "'" + name + "'";
  if (kind.obj == mjOBJ_GEOM) {
    int b = model->geom_bodyid[id];
    std::string body = model.Name(mjOBJ_BODY, b);
    return fmt::format("#{} of body {}", id, body.empty() ? "#" + std::to_string(b) : "'" + body + "'");
  }
  return "#" + std::to_string(id);
}

// One row's elements: same kind of constraint, same written time constant, same source.
struct Group {
  const ArrayKind* kind = nullptr;
  double timeconst = 0;
  std::string source;
  std::vector<int> ids;
  double dampratio = 1;
  double lowest_contact = INFINITY;  // geoms: the lowest time constant their contacts mix to
};

std::string Names(const Model& model, const Group& g) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < g.ids.size() && i < kNamesShown; ++i) {
    names.push_back(Listed(model, *g.kind, g.ids[i]));
  }
  std::string out = fmt::format("{}", fmt::join(names, ", "));
  if (g.ids.size() > kNamesShown) out += fmt::format(" and {} more", g.ids.size() - kNamesShown);
  return out;
}

// Groups the clamped rows (internal::SolrefsBelow) by kind, written time constant and source.
std::vector<Group> Groups(const Model& model, const std::vector<internal::SolrefBelow>& below,
                          const compat::SolrefClasses* classes) {
  const mjModel* m = model.get();
  std::map<std::tuple<int, double, std::string>, Group> groups;
  for (const internal::SolrefBelow& row : below) {
    const ArrayKind* kind = KindOf(row.array);
    if (kind == nullptr) continue;
    int id = static_cast<int>(row.row);
    if (row.array == "dof_solref") id = m->dof_jntid[row.row];
    if (row.array == "opt.o_solref") id = -1;
    std::string source = Source(classes, *kind, id, row.timeconst);
    int order = static_cast<int>(kind - kKinds);
    Group& g = groups[{order, row.timeconst, source}];
    if (std::find(g.ids.begin(), g.ids.end(), id) != g.ids.end()) continue;  // a ball's 3 dofs
    g.kind = kind;
    g.timeconst = row.timeconst;
    g.source = source;
    g.ids.push_back(id);
    g.dampratio = row.dampratio;
    if (!std::isnan(row.contact)) g.lowest_contact = std::min(g.lowest_contact, row.contact);
  }
  std::vector<Group> out;
  for (auto& [key, g] : groups) out.push_back(std::move(g));
  return out;
}

CheckRow ClampRow(const Model& model, const Group& g) {
  const double h = model->opt.timestep, used = 2 * h;
  std::string what = g.kind->obj < 0 ? "opt.o_solref" : fmt::format("{} {}", g.ids.size() == 1 ? g.kind->noun : g.kind->plural, Names(model, g));
  std::string detail = g.kind->constraint;
  if (!g.source.empty()) detail += "; " + g.source;
  if (std::isfinite(g.lowest_contact) && g.lowest_contact != g.timeconst) {
    detail += fmt::format("; their contacts mix it down to {:.3g} s", g.lowest_contact);
  }
  std::string measured = fmt::format(
      "solref timeconst {:.3g} s on {} ({}), raised to {:.3g} s = 2 x timestep {:.3g} s", g.timeconst,
      what, detail, used, h);
  std::string where = g.source.rfind("default class", 0) == 0 ? "in " + g.source
                      : g.kind->obj < 0                      ? "in <option>"
                                                             : "on these " + std::string(g.kind->plural);
  std::string fix = fmt::format(
      "MuJoCo's refsafe limit softens these constraints to {0:.3g} s at this timestep, so the "
      "model does not do what it says: write {1}=\"{0:.3g} {2:g}\" {3} so it says what it does, "
      "or lower the timestep to <= {4:.3g} s so the written {5:.3g} s holds, or disable refsafe "
      "(<flag refsafe=\"disable\"/>) only if the stiffer constraint is stable at this step",
      used, g.kind->attribute, g.dampratio, where, g.timeconst / 2, g.timeconst);
  // several elements: the subject says what they share, which an accept entry can name
  std::string subject =
      g.source.empty()
          ? fmt::format("{} with solref {:.3g} s ({})", g.kind->plural, g.timeconst,
                        g.kind->constraint)
          : fmt::format("{} {} {} ({})", g.kind->plural,
                        g.source.rfind("default class", 0) == 0 ? "of" : "with", g.source,
                        g.kind->constraint);
  CheckRow row = g.ids.size() == 1 && g.kind->obj >= 0
                     ? Make(L, kCheck, ElementOf(model, g.kind->obj, g.ids[0], g.kind->noun),
                            measured, ">= 2 x timestep", CheckStatus::kWarn, fix)
                     : Make(L, kCheck, subject, measured, ">= 2 x timestep", CheckStatus::kWarn,
                            fix);
  return WithNumbers(row, {g.timeconst, "s"}, {used, "s"});
}

// The smallest time constant a constraint of the model starts from (contacts: after mixing),
// and what it belongs to; +infinity when the model has no constraint with a standard solref.
std::pair<double, std::string> Smallest(const Model& model) {
  const mjModel* m = model.get();
  std::pair<double, std::string> best{INFINITY, ""};
  for (const internal::SolrefBelow& row : internal::ActingSolrefsBelow(m, INFINITY)) {
    const ArrayKind* kind = KindOf(row.array);
    if (kind == nullptr) continue;
    double t = row.timeconst;
    int id = static_cast<int>(row.row);
    if (!std::isnan(row.contact)) t = std::max(t, row.contact);
    if (row.array == "dof_solref") id = m->dof_jntid[row.row];
    if (t < best.first) {
      best = {t, fmt::format("{} of {} {}", kind->constraint, kind->noun,
                             Listed(model, *kind, id))};
    }
  }
  return best;
}

}  // namespace

void SolrefClamps(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  const double h = m->opt.timestep, floor = 2 * h;
  if (!compat::ReferenceTimeconstClamped(m)) {
    auto [t, what] = Smallest(model);
    std::string seen = std::isfinite(t) && t < floor
                           ? fmt::format("; the smallest, {:.3g} s ({}), is below 2 x timestep "
                                         "{:.3g} s: MuJoCo runs it as written",
                                         t, what, floor)
                           : "";
    out->push_back(Make(L, kCheck, "", "refsafe disabled", "", CheckStatus::kSkip,
                        "<flag refsafe=\"disable\"/>: MuJoCo clamps no solref timeconst, so "
                        "every constraint runs as written" + seen));
    return;
  }
  std::vector<internal::SolrefBelow> below = internal::SolrefsBelow(m, floor);
  if (below.empty()) {
    auto [t, what] = Smallest(model);
    std::string measured = std::isfinite(t)
                               ? fmt::format("smallest solref timeconst {:.3g} s ({})", t, what)
                               : "no constraint with a standard solref";
    out->push_back(WithNumbers(
        Make(L, kCheck, "", measured, fmt::format(">= 2 x timestep ({:.3g} s)", floor),
             CheckStatus::kPass,
             "every contact (its geoms' solrefs mixed as MuJoCo mixes them), explicit pair, "
             "joint and tendon limit, friction loss and equality keeps the solref timeconst it "
             "was written with: none is below the 2 x timestep MuJoCo's refsafe raises it to"),
        {std::isfinite(t) ? t : NAN, std::isfinite(t) ? "s" : ""}, {floor, "s"}));
    return;
  }
  std::optional<compat::SolrefClasses> classes;
  try {
    classes = compat::SolrefDefaultClasses(model.xml_text(), model.file(), m);
  } catch (const MujocoError&) {
    classes = std::nullopt;  // the source no longer parses
  }
  std::vector<Group> groups = Groups(model, below, classes ? &*classes : nullptr);
  int listed = 0;
  for (const Group& g : groups) {
    if (listed++ < kMaxListed) out->push_back(ClampRow(model, g));
  }
  ListedNote(L, kCheck, "groups of clamped solrefs", static_cast<int>(groups.size()), out);
}

}  // namespace plumb::audit
