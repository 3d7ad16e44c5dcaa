#include "crosscheck/support_check.h"

#include <fmt/format.h>

#include <functional>

#include "core/mujoco_compat.h"

namespace plumb::internal {
namespace {

using Detect = std::function<std::vector<CheckElement>(const Model&, const GeomPairs&)>;

// One entry of the table: a feature one engine accepts and computes differently.
struct SupportRule {
  const char* id;
  const char* engine;  // "warp", "mjx"
  const char* behaviour;
  const char* fix;
  Detect detect;
};

CheckElement Option(const char* name) { return {"option", name, -1}; }

Detect OptionIf(const char* name, std::function<bool(const mjOption&)> when) {
  return [name, when](const Model& model, const GeomPairs&) {
    return when(model->opt) ? std::vector<CheckElement>{Option(name)} : std::vector<CheckElement>{};
  };
}

std::string GeomPairName(const Model& model, int a, int b) {
  auto name = [&](int g) {
    const std::string n = model.Name(mjOBJ_GEOM, g);
    return n.empty() ? "#" + std::to_string(g) : n;
  };
  return name(a) + " / " + name(b);
}

// Geom pairs of CPU MuJoCo's run where one geom is of type `a` and the other of type `b` (any
// type when `b` is -1).
Detect TouchingPairs(int a, int b) {
  return [a, b](const Model& model, const GeomPairs& touching) {
    std::vector<CheckElement> out;
    for (auto [g1, g2] : touching) {
      const int t1 = model->geom_type[g1], t2 = model->geom_type[g2];
      if ((t1 == a && (b < 0 || t2 == b)) || (t2 == a && (b < 0 || t1 == b))) {
        out.push_back({"geom pair", GeomPairName(model, g1, g2), -1});
      }
    }
    return out;
  };
}

Detect Plugins() {
  return [](const Model& model, const GeomPairs&) {
    std::vector<CheckElement> out;
    for (int p = 0; p < compat::PluginCount(model.get()); ++p) out.push_back({"plugin", "", p});
    return out;
  };
}

// Actuators in a group the model disables.
Detect DisabledActuators() {
  return [](const Model& model, const GeomPairs&) {
    std::vector<CheckElement> out;
    const int groups = compat::DisabledActuatorGroups(model.get());
    for (int u = 0; u < model->nu && groups != 0; ++u) {
      const int g = model->actuator_group[u];
      if (g >= 0 && g < 31 && (groups & (1 << g))) {
        out.push_back({"actuator", model.Name(mjOBJ_ACTUATOR, u), u});
      }
    }
    return out;
  };
}

Detect WhenNativeCcd(Detect inner) {
  return [inner](const Model& model, const GeomPairs& touching) {
    return compat::NativeCcdDisabled(model.get()) ? std::vector<CheckElement>{}
                                                  : inner(model, touching);
  };
}

Detect FlagsMjxIgnores() {
  return [](const Model& model, const GeomPairs&) {
    std::vector<CheckElement> out;
    for (const std::string& flag : compat::FlagsMjxIgnores(model.get())) {
      out.push_back({"flag", flag, -1});
    }
    return out;
  };
}

Detect StateSize(const char* what, long (*size)(const mjModel*)) {
  return [what, size](const Model& model, const GeomPairs&) {
    return size(model.get()) > 0 ? std::vector<CheckElement>{{what, "", -1}}
                                 : std::vector<CheckElement>{};
  };
}

Detect MaxContactPoints() {
  return [](const Model& model, const GeomPairs&) {
    std::vector<CheckElement> out;
    for (const char* name : {"max_contact_points", "max_geom_pairs"}) {
      const int id = mj_name2id(model.get(), mjOBJ_NUMERIC, name);
      if (id >= 0) out.push_back({"numeric", name, id});
    }
    return out;
  };
}

// The table (docs/crosscheck.md gives each entry's source in the engines' code, as read for
// mujoco-warp 4.0.0 and mujoco-mjx 3.17.0, and the measurements behind it).
const std::vector<SupportRule>& Table() {
  static const char* kBoxBoxFix =
      "read the stages.contacts row; with Warp, <flag nativeccd=\"disable\"/> selects its port of "
      "CPU MuJoCo's box-box";
  static const std::vector<SupportRule> kTable = {
      {"support.actuator_group", "warp",
       "ignores opt.actuatorgroupdisable: this actuator, disabled on CPU MuJoCo, acts in the "
       "engine",
       "remove the actuator, or zero its control, instead of disabling its group",
       DisabledActuators()},
      {"support.actuator_group", "mjx",
       "ignores opt.actuatorgroupdisable: this actuator, disabled on CPU MuJoCo, acts in the "
       "engine",
       "remove the actuator, or zero its control, instead of disabling its group",
       DisabledActuators()},
      {"support.box_box", "warp",
       "box-box collisions go through its GJK/EPA with polygon clipping: at most 4 contacts per "
       "pair where CPU MuJoCo finds up to 8",
       kBoxBoxFix, WhenNativeCcd(TouchingPairs(mjGEOM_BOX, mjGEOM_BOX))},
      {"support.box_box", "mjx",
       "box-box collisions fill 4 contact slots, repeating points, with depths and positions of "
       "its own",
       "read the stages.contacts row", TouchingPairs(mjGEOM_BOX, mjGEOM_BOX)},
      {"support.hfield", "warp",
       "heightfield collisions go through its convex path with a per-pair cap on contacts",
       "read the stages.contacts row", TouchingPairs(mjGEOM_HFIELD, -1)},
      {"support.hfield", "mjx",
       "heightfield collisions: only against spheres, capsules, boxes and meshes, by its own "
       "algorithm",
       "read the stages.contacts row", TouchingPairs(mjGEOM_HFIELD, -1)},
      {"support.plugin", "warp",
       "runs geom (SDF) plugins only: any other plugin's effect is missing",
       "keep plugins out of the model the policy trains on", Plugins()},
      {"support.plugin", "mjx", "does not run plugins: their effect is missing",
       "keep plugins out of the model the policy trains on", Plugins()},
      {"support.noslip", "mjx",
       "ignores opt.noslip_iterations: the noslip post-solver does not run, so contacts slide "
       "where CPU MuJoCo's hold",
       "set noslip_iterations=\"0\" for the check, or train on MuJoCo Warp, which runs noslip",
       OptionIf("noslip_iterations", [](const mjOption& o) { return o.noslip_iterations > 0; })},
      {"support.delay", "mjx",
       "ignores actuator and sensor delays (the history buffer): controls act and sensors read "
       "at once",
       "train with the delay modelled in the policy's environment, or on MuJoCo Warp",
       StateSize("delay history", compat::HistorySize)},
      {"support.plastic", "mjx", "ignores plasticity: the plastic state never changes",
       "keep plasticity out of the model the policy trains on",
       StateSize("plastic state", compat::PlasticSize)},
      {"support.flag", "mjx",
       "accepts this option flag and never reads it: it runs as if the flag were at its default",
       "clear the flag, or accept the difference", FlagsMjxIgnores()},
      {"support.contact_cap", "mjx",
       "keeps only the deepest contacts (numeric max_contact_points / max_geom_pairs): contacts "
       "CPU MuJoCo keeps are dropped",
       "raise the numeric, or read the stages.contacts row", MaxContactPoints()},
  };
  return kTable;
}

}  // namespace

std::vector<CheckRow> SupportRows(const Model& model, const EngineInfo& engine,
                                  const std::string& plumb_mujoco, const GeomPairs& touching) {
  std::vector<CheckRow> rows;
  CheckRow versions;
  versions.id = "support.versions";
  versions.section = "support";
  versions.title = "the engine runs on the same MuJoCo as plumb";
  versions.measured_text =
      fmt::format("{} {} ({}) on MuJoCo {}, {} on {}", engine.engine, engine.engine_version,
                  engine.backend, engine.mujoco_version, engine.precision, engine.device);
  versions.reference_text = "plumb on MuJoCo " + plumb_mujoco;
  if (engine.mujoco_version == plumb_mujoco) {
    versions.status = CheckStatus::kPass;
    versions.explanation =
        "the same MuJoCo compiles the model on both sides; the engine computes "
        "in " +
        engine.precision +
        ", whose rounding the trajectory check's "
        "chaos baseline measures";
  } else {
    versions.status = CheckStatus::kWarn;
    versions.explanation = fmt::format(
        "the engine's environment has MuJoCo {} and plumb was built with {}: the model is compiled "
        "by different versions, and a difference may come from the versions, not the engine",
        engine.mujoco_version, plumb_mujoco);
    versions.fix = "build plumb against MuJoCo " + engine.mujoco_version +
                   " (make MUJOCO=...), the version the engines' wheels support";
  }
  rows.push_back(versions);
  const std::size_t before = rows.size();
  for (const SupportRule& rule : Table()) {
    if (engine.engine != rule.engine) continue;
    for (const CheckElement& element : rule.detect(model, touching)) {
      CheckRow row;
      row.id = rule.id;
      row.section = "support";
      row.title = "computed differently by the engine";
      row.status = CheckStatus::kWarn;
      row.finding = rule.behaviour;
      row.element = element;
      row.explanation = rule.behaviour;
      row.fix = rule.fix;
      rows.push_back(row);
    }
  }
  if (rows.size() == before) {
    CheckRow row;
    row.id = "support.table";
    row.section = "support";
    row.title = "nothing the engine is known to compute differently";
    row.status = CheckStatus::kPass;
    row.explanation = fmt::format(
        "the model uses nothing that {} is known to compute differently "
        "(docs/crosscheck.md lists what is known)",
        engine.engine);
    rows.push_back(row);
  }
  return rows;
}

CheckRow RefusalRow(const Model& model, const std::string& engine, const std::string& message) {
  CheckRow row;
  row.id = "support.refused";
  row.section = "support";
  row.status = CheckStatus::kFail;
  row.title = "the engine accepts the model";
  row.measured_text = message;
  row.explanation = fmt::format("{} refuses this model: {}", engine, message);
  row.fix = "change what it names, or keep this model on CPU MuJoCo";
  const mjOption& o = model->opt;
  if (message.find("PGS") != std::string::npos && o.solver == mjSOL_PGS) {
    row.element = Option("solver");
  } else if (message.find("ntegrator") != std::string::npos ||
             message.find("IMPLICIT") != std::string::npos) {
    row.element = Option("integrator");
  } else if (message.find("oslip") != std::string::npos) {
    row.element = Option("noslip_iterations");
  } else if (message.find("cone") != std::string::npos) {
    row.element = Option("cone");
  }
  return row;
}

CheckRow CapacityRow(long contacts, long constraints) {
  CheckRow row;
  if (contacts <= 0 && constraints <= 0) return row;
  row.id = "support.capacity";
  row.section = "support";
  row.status = CheckStatus::kFail;
  row.measured = {static_cast<double>(contacts + constraints), ""};
  row.measured_text =
      fmt::format("{} contact(s) and {} constraint row(s) dropped", contacts, constraints);
  row.explanation =
      "the engine ran out of room for contacts or constraint rows and dropped "
      "them without an error: its physics is missing those contacts";
  row.fix = "raise the engine's nconmax / njmax where the policy trains";
  return row;
}

}  // namespace plumb::internal
