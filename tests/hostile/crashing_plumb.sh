#!/bin/sh
# A plumb that crashes on every command: HostileModelsSeesACrash checks that the hostile-model
# driver reports it (exit 1, "killed by signal 11") rather than counting it as clean.
kill -SEGV $$
