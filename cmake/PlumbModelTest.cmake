# plumb_add_model_test: accept a MuJoCo model in a project's own CI with CTest.
#
#   find_package(plumb REQUIRED)
#   enable_testing()
#   plumb_add_model_test(NAME robot MODEL robot.xml
#                        [SNAPSHOT robot.snap.json] [SCENARIO stand.toml]
#                        [ACCEPT accepted.toml] [STRICT] [TOL 1e-6] [SET "qpos[hinge]=0.7" ...])
#
# registers the CTest tests
#   <NAME>.audit  plumb audit MODEL [--scenario SCENARIO] [--accept ACCEPT] [--strict]: fails
#                 on any FAIL (and on WARN with STRICT) that the accept list ACCEPT (reviewed
#                 findings with their reasons) does not accept; an entry of ACCEPT that no
#                 longer matches a finding is a WARN
#   <NAME>.diff   plumb diff SNAPSHOT MODEL --tol TOL: fails on any change beyond TOL
# and the target <NAME>.snapshot, which rewrites SNAPSHOT from the current model when a
# change is intended (cmake --build . --target <NAME>.snapshot, then commit the file).
# Relative paths are taken from the calling CMakeLists.txt's folder. PLUMB_EXECUTABLE
# names the plumb tool (set by find_package(plumb)).

function(plumb_add_model_test)
  cmake_parse_arguments(ARG "STRICT" "NAME;MODEL;SNAPSHOT;SCENARIO;ACCEPT;TOL" "SET" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_MODEL)
    message(FATAL_ERROR "plumb_add_model_test: NAME and MODEL are required")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "plumb_add_model_test(${ARG_NAME}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT PLUMB_EXECUTABLE)
    message(FATAL_ERROR "plumb_add_model_test: PLUMB_EXECUTABLE is not set; call find_package(plumb)")
  endif()
  if(NOT ARG_TOL)
    set(ARG_TOL 1e-6)
  endif()
  get_filename_component(model "${ARG_MODEL}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT EXISTS "${model}")
    message(FATAL_ERROR "plumb_add_model_test(${ARG_NAME}): model ${model} does not exist")
  endif()
  set(sets "")
  foreach(s IN LISTS ARG_SET)
    list(APPEND sets --set "${s}")
  endforeach()

  set(audit ${PLUMB_EXECUTABLE} audit "${model}" ${sets}
      --repro "${CMAKE_CURRENT_BINARY_DIR}/${ARG_NAME}-repro")
  if(ARG_SCENARIO)
    get_filename_component(scenario "${ARG_SCENARIO}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
    list(APPEND audit --scenario "${scenario}")
  endif()
  if(ARG_ACCEPT)
    get_filename_component(accept "${ARG_ACCEPT}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
    if(NOT EXISTS "${accept}")
      message(FATAL_ERROR "plumb_add_model_test(${ARG_NAME}): accept list ${accept} does not exist")
    endif()
    list(APPEND audit --accept "${accept}")
  endif()
  if(ARG_STRICT)
    list(APPEND audit --strict)
  endif()
  add_test(NAME ${ARG_NAME}.audit COMMAND ${audit})

  if(ARG_SNAPSHOT)
    get_filename_component(snapshot "${ARG_SNAPSHOT}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
    add_test(NAME ${ARG_NAME}.diff
             COMMAND ${PLUMB_EXECUTABLE} diff "${snapshot}" "${model}" ${sets} --tol ${ARG_TOL})
    add_custom_target(${ARG_NAME}.snapshot
      COMMAND ${PLUMB_EXECUTABLE} snapshot "${model}" ${sets} -o "${snapshot}"
      COMMENT "plumb: writing the snapshot of ${ARG_MODEL} to ${ARG_SNAPSHOT}"
      VERBATIM)
  endif()
endfunction()
