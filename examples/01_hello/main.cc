// Chapter 1's first credible simulation, step by step: load a pendulum, start it at
// 0.7 rad, step it headless with mj_step to 2 s and print the angle and angular
// velocity every 0.1 s.
//
// Usage: hello MODEL.xml [INITIAL_ANGLE_RAD]
// Expected first lines for models/pendulum.xml (MuJoCo 2.2.2):
//   t= 0.10 q=0.65403 dq=-0.89118
//   t= 0.20 q=0.52386 dq=-1.66939

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  // check the arguments before touching MuJoCo
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s MODEL.xml [INITIAL_ANGLE_RAD]\n", argv[0]);
    return EXIT_FAILURE;
  }
  double initial_angle = 0.7;  // rad: off the vertical, so gravity has a torque to apply
  if (argc == 3) {
    char* end = nullptr;
    initial_angle = std::strtod(argv[2], &end);
    if (*end != '\0' || !std::isfinite(initial_angle)) {
      std::fprintf(stderr, "%s: initial angle '%s' is not a number of radians\n", argv[0], argv[2]);
      return EXIT_FAILURE;
    }
  }

  // parse and compile; on failure print MuJoCo's whole diagnosis, not just "failed"
  char error[1024] = {0};
  mjModel* m = mj_loadXML(argv[1], nullptr, error, sizeof(error));
  if (!m) {
    std::fprintf(stderr, "cannot load %s:\n%s\n", argv[1], error);
    return EXIT_FAILURE;
  }

  // one simulation instance of the model
  mjData* d = mj_makeData(m);
  if (!d) {
    std::fprintf(stderr, "cannot allocate mjData for %s\n", argv[1]);
    mj_deleteModel(m);
    return EXIT_FAILURE;
  }

  // set the initial state, then make the derived quantities agree with it
  if (m->nq > 0) d->qpos[0] = initial_angle;
  mj_forward(m, d);

  // step to 2 s and print every 0.1 s; count steps so the print times are exact
  const double until = 2.0, every = 0.1;
  const long steps = std::lround(until / m->opt.timestep);
  const long stride = std::lround(every / m->opt.timestep);
  for (long step = 1; step <= steps; ++step) {
    mj_step(m, d);
    if (stride > 0 && step % stride == 0) {
      double q = m->nq > 0 ? d->qpos[0] : 0.0;
      double dq = m->nv > 0 ? d->qvel[0] : 0.0;
      std::printf("t=%5.2f q=%.5f dq=%.5f\n", step * m->opt.timestep, q, dq);
    }
  }

  // data depends on the model's layout: free it first
  mj_deleteData(d);
  mj_deleteModel(m);
  return EXIT_SUCCESS;
}
