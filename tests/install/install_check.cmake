# Installs plumb into a scratch prefix and builds a small project that uses it with
# find_package(plumb), then runs that project's program and the installed CLI.
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}"
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install/consumer" -B "${WORK_DIR}/consumer"
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring a find_package(plumb) project failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/consumer"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "building a find_package(plumb) project failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${WORK_DIR}/consumer/consumer" "${prefix}/share/plumb/models/pendulum.xml"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "q\\(0.5\\) = -0.16156")
  message(FATAL_ERROR "the consumer printed:\n${out}")
endif()
execute_process(COMMAND "${prefix}/bin/plumb" --version RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "plumb")
  message(FATAL_ERROR "the installed plumb CLI failed: ${out}")
endif()
# the installed command-line tool verifies the chapter's pendulum from the installed model
execute_process(COMMAND "${prefix}/bin/plumb" verify "${prefix}/share/plumb/models/pendulum.xml"
    --set "qpos[hinge]=0.7" --all
  RESULT_VARIABLE rc OUTPUT_VARIABLE cli_out ERROR_VARIABLE cli_err)
if(rc OR NOT cli_out MATCHES "analytic.period")
  message(FATAL_ERROR "the installed plumb CLI failed to verify the pendulum (${rc}):\n${cli_out}\n${cli_err}")
endif()

# plumb crosscheck's engine adapter, its locks and the scripts that make an environment are
# installed beside plumb, where the installed plumb looks first
foreach(file adapter.py _warp.py _mjx.py requirements-warp.txt requirements-mjx.txt make-venv.sh
    test-venv.sh)
  if(NOT EXISTS "${prefix}/share/plumb/engines/${file}")
    message(FATAL_ERROR "make install did not install share/plumb/engines/${file}")
  endif()
endforeach()

# built against a release folder (a wheel version in the cache), the installed plumb
# carries that MuJoCo beside its library and loads it from there, not from the cache
file(GLOB bundled "${prefix}/lib*/libmujoco.so*")
if(bundled)
  file(REAL_PATH "${prefix}" real_prefix)
  string(FIND "${out}" "from ${real_prefix}/" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the installed plumb does not load the MuJoCo installed with it:\n${out}")
  endif()
  execute_process(COMMAND ldd "${WORK_DIR}/consumer/consumer" OUTPUT_VARIABLE linked)
  string(FIND "${linked}" "${prefix}/" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the consumer does not load the installed MuJoCo:\n${linked}")
  endif()
endif()

# the model-acceptance helper from an installed plumb: examples/model_ci passes as shipped
set(ci_src "${WORK_DIR}/model_ci-src")
file(COPY "${SOURCE_DIR}/examples/model_ci/" DESTINATION "${ci_src}")
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${ci_src}" -B "${WORK_DIR}/model_ci" -DCMAKE_PREFIX_PATH=${prefix}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring examples/model_ci failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --output-on-failure
  WORKING_DIRECTORY "${WORK_DIR}/model_ci" RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "arm.audit" OR NOT out MATCHES "arm.diff")
  message(FATAL_ERROR "examples/model_ci's tests failed:\n${out}")
endif()

# an accept-list entry that matches no finding of the arm is stale: STRICT fails arm.audit
file(READ "${ci_src}/accepted.toml" accepted)
file(APPEND "${ci_src}/accepted.toml"
  "[[accept]]\ncheck = \"inertia.size\"\nelement = \"body 'fore'\"\nreason = \"CAD\"\n")
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --output-on-failure -R arm.audit
  WORKING_DIRECTORY "${WORK_DIR}/model_ci" RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc OR NOT out MATCHES "accept\\.stale +[^ ]*accepted\\.toml:16: inertia\\.size about body 'fore'")
  message(FATAL_ERROR "arm.audit did not report the stale accept entry:\n${out}")
endif()
file(WRITE "${ci_src}/accepted.toml" "${accepted}")

# and it notices a change: more damping at the shoulder fails arm.diff, naming the field
file(READ "${ci_src}/arm.xml" xml)
string(REPLACE "damping=\"3\"" "damping=\"4\"" xml "${xml}")
file(WRITE "${ci_src}/arm.xml" "${xml}")
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --output-on-failure -R arm.diff
  WORKING_DIRECTORY "${WORK_DIR}/model_ci" RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc OR NOT out MATCHES "dof_damping\\[shoulder\\]")
  message(FATAL_ERROR "arm.diff did not catch the changed damping:\n${out}")
endif()
