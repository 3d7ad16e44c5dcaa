// One engine adapter, spoken to in plumb's terms: the model plumb runs goes in as a file plus
// the edits that make it the same model, states go in from mjData, and what comes back is
// unpacked into per-world arrays, contacts and constraint rows (docs/engine-protocol.md).

#ifndef PLUMB_SRC_CROSSCHECK_ENGINE_SESSION_H_
#define PLUMB_SRC_CROSSCHECK_ENGINE_SESSION_H_

#include <memory>
#include <string>
#include <vector>

#include "crosscheck/engine_process.h"
#include "plumb/crosscheck.h"
#include "plumb/model.h"

namespace plumb::internal {

// The command that makes `engine`'s environment ahead of a run ("plumb crosscheck --setup
// --engine warp"), which the messages about a missing environment tell the user to run.
std::string EngineSetupCommand(const std::string& engine);

// One contact as both sides report it.
struct StageContact {
  int world = 0;
  int geom1 = -1, geom2 = -1;
  double dist = 0;
  double pos[3] = {0, 0, 0};
  double frame[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // rows: the normal, then two tangents
  int dim = 3;
  double force[6] = {0, 0, 0, 0, 0, 0};  // mj_contactForce, in the contact frame
};

// One constraint row; for a contact row `id` is the contact's index in its world's list.
struct StageConstraint {
  int world = 0;
  int type = 0;  // mjtConstraint
  int id = 0;
  double pos = 0, force = 0;
};

// Everything the stage check compares, for W worlds (per-world arrays are row-major).
struct StageValues {
  int worlds = 0;
  std::vector<double> xpos, xquat, qM, qacc, sensordata, next_qpos, next_qvel, next_act;
  std::vector<StageContact> contacts;
  std::vector<StageConstraint> constraints;
  long overflow_contacts = 0, overflow_constraints = 0;
};

// The same quantities from CPU MuJoCo: forward at each state, then one step.
StageValues CpuStages(const Model& model, const std::vector<const mjData*>& states);

// Per-world values of a model field, for worlds that differ in their parameters.
struct WorldField {
  std::string field;           // "body_mass"
  std::vector<double> values;  // [W * size]
};

struct EngineRollout {
  long rows = 0;                        // recorded states per world (start included)
  std::vector<double> qpos, qvel, act;  // [rows][W * size]
  std::vector<double> ncon_max;         // [W]
  long overflow_contacts = 0, overflow_constraints = 0;
  std::vector<std::string> unvaried;  // "body_mass: reason"
};

class EngineSession {
 public:
  // Starts the adapter and says hello. @throws UnavailableError when the python or the
  // adapter is missing; EngineError when it does not answer or speaks another protocol.
  EngineSession(const EngineSetup& setup, const std::string& engine, const std::string& device,
                StopToken stop);
  ~EngineSession();

  const EngineInfo& info() const { return info_; }

  // Sends the model: its file and every element where `model` differs from that file freshly
  // compiled. Returns how ("XML + 3 edits"). @throws EngineRefused when the engine refuses it.
  std::string Load(const Model& model);

  StageValues Stages(const Model& model, const std::vector<const mjData*>& states);

  // Open-loop runs: `ctrl` holds the controls before each step, [steps][W * nu].
  EngineRollout Rollout(const Model& model, const std::vector<const mjData*>& starts,
                        const std::vector<double>& ctrl, long steps, long every,
                        const std::vector<WorldField>& fields);

  // World-steps per second of W worlds from `start`, and the first step's (compiling) time.
  std::pair<double, double> Throughput(const Model& model, const mjData* start, int worlds,
                                       long steps);

 private:
  EngineReply Ask(const nlohmann::json& header, const std::vector<EngineArray>& arrays);

  std::unique_ptr<EngineProcess> process_;
  EngineInfo info_;
  double timeout_ = 0;
  StopToken stop_;
  std::string temp_dir_;  // a model given as text is written here
};

// @throws ArgumentError naming the engines plumb knows (CrosscheckEngines) when `engine` is not
// one of them.
void RequireKnownEngine(const std::string& engine);

// The model-array and option elements in which `model` differs from `base` (the same file
// freshly compiled), as the adapter applies them: [field, flat index, value].
nlohmann::json ModelEdits(const Model& base, const Model& model);

// Every element of model field `field` ("body_mass", "opt.gravity") as doubles.
std::vector<double> FieldValues(const Model& model, const std::string& field);

// Writes edits made by ModelEdits into `model` (of the same structure).
void ApplyEdits(const nlohmann::json& edits, Model& model);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CROSSCHECK_ENGINE_SESSION_H_
