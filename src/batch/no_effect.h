// Why a randomized or swept model element may change nothing: the one reason `plumb sweep`'s
// and `plumb rollout`'s notes give (and Python's), which reads the model where the field is a
// geom's contact parameter (geom priority decides whose parameters a contact takes).

#ifndef PLUMB_SRC_BATCH_NO_EFFECT_H_
#define PLUMB_SRC_BATCH_NO_EFFECT_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"

namespace plumb::internal {

// The likely reason the elements `paths` changed no metric, one paragraph. With `model` (may be
// null) a geom's friction, solref, solimp, solmix or condim is judged against the geoms it may
// touch: MuJoCo takes a contact's parameters from the geom of higher priority, and only between
// geoms of equal priority the larger friction (and solref/solimp mixed by solmix).
std::string WhyNoEffect(const Model* model, const std::vector<Path>& paths);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_BATCH_NO_EFFECT_H_
