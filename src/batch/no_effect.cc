// Why a varied element may change nothing (src/batch/no_effect.h).

#include "batch/no_effect.h"

#include <fmt/format.h>

#include <map>
#include <set>

namespace plumb::internal {
namespace {

// The geom contact fields and how many numbers each geom has in them.
int GeomContactWidth(const std::string& field) {
  if (field == "geom_friction") return 3;
  if (field == "geom_solref") return mjNREF;
  if (field == "geom_solimp") return mjNIMP;
  if (field == "geom_solmix" || field == "geom_condim") return 1;
  return 0;
}

std::string GeomLabel(const Model& model, int g) {
  std::string name = model.Name(mjOBJ_GEOM, g);
  if (!name.empty()) return "'" + name + "'";
  std::string body = model.Name(mjOBJ_BODY, model->geom_bodyid[g]);
  return body.empty() ? fmt::format("#{}", g) : fmt::format("#{} of body '{}'", g, body);
}

// "'a', 'b', 'c' and 4 more"
std::string Few(const Model& model, const std::vector<int>& geoms) {
  std::string out;
  for (std::size_t i = 0; i < geoms.size() && i < 3; ++i) {
    out += (i ? ", " : "") + GeomLabel(model, geoms[i]);
  }
  if (geoms.size() > 3) out += fmt::format(" and {} more", geoms.size() - 3);
  return out;
}

// Why geom `g`'s `field` may have no say in its contacts.
std::string WhyGeomNoEffect(const Model& model, int g, const std::string& field) {
  const mjModel* m = model.get();
  for (int p = 0; p < m->npair; ++p) {
    if (m->pair_geom1[p] == g || m->pair_geom2[p] == g) {
      return fmt::format(
          "Geom {} is in an explicit contact pair, which sets its own friction, solref and solimp: "
          "vary the pair's (pair_friction, pair_solref, ...).",
          GeomLabel(model, g));
    }
  }
  // the geoms it may touch: another body's, passing contype/conaffinity
  std::vector<int> higher, equal, lower;
  for (int h = 0; h < m->ngeom; ++h) {
    if (h == g || m->geom_bodyid[h] == m->geom_bodyid[g]) continue;
    bool meets = (m->geom_contype[g] & m->geom_conaffinity[h]) ||
                 (m->geom_contype[h] & m->geom_conaffinity[g]);
    if (!meets) continue;
    int a = m->geom_priority[g], b = m->geom_priority[h];
    (b > a ? higher : b == a ? equal : lower).push_back(h);
  }
  std::string geom = fmt::format("Geom {} (priority {})", GeomLabel(model, g), m->geom_priority[g]);
  if (higher.empty() && equal.empty() && lower.empty()) {
    return geom + " can touch no geom (contype/conaffinity), so its contact parameters are "
                  "never used.";
  }
  std::string out = geom;
  if (!higher.empty()) {
    std::set<int> priorities;
    for (int h : higher) priorities.insert(m->geom_priority[h]);
    out += fmt::format(
        " meets geoms of higher priority ({}: {}): MuJoCo takes the friction, solref and solimp "
        "of a contact from its higher-priority geom, so in those contacts this geom's have no "
        "say; vary theirs, or give this geom their priority.",
        priorities.size() == 1 ? fmt::format("priority {}", *priorities.begin()) : "priority",
        Few(model, higher));
  } else {
    out += ":";
  }
  if (!equal.empty()) {
    std::string rule =
        field == "geom_friction"
            ? "a contact takes the larger friction of its two geoms, so lowering this geom's "
              "friction below its partner's changes nothing; vary the partner's too"
            : "a contact mixes both geoms' solref/solimp by their solmix weights; a geom whose "
              "weight is 0 has no say";
    out += fmt::format(" {} geoms of its own priority ({}), {}.", higher.empty() ? "with" : "With",
                       Few(model, equal), rule);
  }
  if (!lower.empty()) {
    out += fmt::format(" {} own parameters decide its contacts with geoms of lower priority ({}).",
                       higher.empty() && equal.empty() ? "its" : "Its", Few(model, lower));
  }
  return out + " A geom that touches nothing in this run has no say at all.";
}

}  // namespace

std::string WhyNoEffect(const Model* model, const std::vector<Path>& paths) {
  std::string field = paths.empty() ? "" : paths.front().field;
  int width = GeomContactWidth(field);
  if (model && width > 0) {
    std::vector<std::string> reasons;
    std::set<int> seen;
    for (const Path& p : paths) {
      int g = static_cast<int>(p.first / width);
      if (p.field != field || g >= (*model)->ngeom || !seen.insert(g).second) continue;
      std::string why = WhyGeomNoEffect(*model, g, field);
      if (reasons.size() < 2) reasons.push_back(why);
    }
    std::string out;
    for (const std::string& r : reasons) out += (out.empty() ? "" : " ") + r;
    if (seen.size() > reasons.size()) {
      out += fmt::format(" ({} more geoms are varied.)", seen.size() - reasons.size());
    }
    if (!out.empty()) return out;
  }
  if (field == "geom_friction") {
    return "A geom's friction acts only in its contacts, and MuJoCo gives a contact the "
           "friction of its higher-priority geom, or between geoms of equal priority the larger "
           "of the two, so lowering one geom's friction below its partner's changes nothing; "
           "vary the other geom's friction too, or use geom priority.";
  }
  if (field == "geom_solref" || field == "geom_solimp" || field == "geom_solmix") {
    return "A contact mixes both geoms' solref/solimp by their solmix weights; a geom whose "
           "weight is 0, or that touches nothing in this run, has no say.";
  }
  return "The element may take no part in this run (a geom that touches nothing, a joint "
         "that does not move, a disabled actuator), or the metrics do not depend on it.";
}

}  // namespace plumb::internal
