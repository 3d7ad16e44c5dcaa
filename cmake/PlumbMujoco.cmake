# Finds MuJoCo for plumb and for projects that use an installed plumb.
#
# Default: Debian's libmujoco-dev through its CMake package (find_package(mujoco)).
# With MUJOCO_ROOT set to an official release folder (include/mujoco/*.h and
# lib/libmujoco.so), an imported target mujoco::mujoco is made from that folder
# instead, and PLUMB_MUJOCO_LIBDIR names the folder to put in RPATHs.

function(plumb_find_mujoco)
  if(TARGET mujoco::mujoco)
    return()
  endif()
  if(MUJOCO_ROOT)
    find_path(PLUMB_MUJOCO_INCLUDE_DIR mujoco/mujoco.h
      PATHS "${MUJOCO_ROOT}/include" NO_DEFAULT_PATH)
    find_library(PLUMB_MUJOCO_LIBRARY NAMES mujoco
      PATHS "${MUJOCO_ROOT}/lib" "${MUJOCO_ROOT}/lib64" NO_DEFAULT_PATH)
    if(NOT PLUMB_MUJOCO_INCLUDE_DIR OR NOT PLUMB_MUJOCO_LIBRARY)
      message(FATAL_ERROR
        "MUJOCO_ROOT=${MUJOCO_ROOT} does not look like a MuJoCo release folder: expected "
        "include/mujoco/mujoco.h and lib/libmujoco.so inside it.")
    endif()
    add_library(mujoco::mujoco SHARED IMPORTED GLOBAL)
    set_target_properties(mujoco::mujoco PROPERTIES
      IMPORTED_LOCATION "${PLUMB_MUJOCO_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${PLUMB_MUJOCO_INCLUDE_DIR}")
    get_filename_component(libdir "${PLUMB_MUJOCO_LIBRARY}" DIRECTORY)
    set(PLUMB_MUJOCO_LIBDIR "${libdir}" CACHE INTERNAL "MuJoCo library folder")
    message(STATUS "plumb: MuJoCo from MUJOCO_ROOT: ${PLUMB_MUJOCO_LIBRARY}")
  else()
    find_package(mujoco REQUIRED CONFIG HINTS ${PLUMB_MUJOCO_HINT})
    # Debian's config lists /usr/include/libqhull_r/, which only libqhull-dev installs and
    # MuJoCo's public headers never include: drop include folders that do not exist
    get_target_property(dirs mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
    set(existing "")
    foreach(dir IN LISTS dirs)
      if(EXISTS "${dir}")
        list(APPEND existing "${dir}")
      endif()
    endforeach()
    set_target_properties(mujoco::mujoco PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${existing}")
    get_target_property(loc mujoco::mujoco LOCATION)
    get_filename_component(libdir "${loc}" DIRECTORY)
    set(PLUMB_MUJOCO_LIBDIR "${libdir}" CACHE INTERNAL "MuJoCo library folder")
    message(STATUS "plumb: MuJoCo ${mujoco_VERSION} from ${loc}")
  endif()
endfunction()
