/* The bare program plumb run is measured against (bench/whole_process_overhead.sh): load a
 * model as MuJoCo's own samples do, step it with mj_step a given number of times, free it.
 *
 *   cc bench/bare_step.c -I MUJOCO/include -L MUJOCO/lib -lmujoco -o bare_step
 *   ./bare_step humanoid.xml 20000
 */
#include <stdio.h>
#include <stdlib.h>

#include <mujoco/mujoco.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s MODEL.xml STEPS\n", argv[0]);
    return 2;
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(argv[1], NULL, error, sizeof(error));
  if (!m) {
    fprintf(stderr, "cannot load %s: %s\n", argv[1], error);
    return 2;
  }
  mjData* d = mj_makeData(m);
  long steps = atol(argv[2]);
  for (long i = 0; i < steps; ++i) mj_step(m, d);
  printf("qpos[0] after %ld steps: %.17g\n", steps, d->qpos[0]);
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
