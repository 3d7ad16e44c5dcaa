# Finds MuJoCo for plumb and for projects that use an installed plumb.
#
# Default: Debian's libmujoco-dev through its CMake package (find_package(mujoco)).
# With MUJOCO_ROOT set to an official release folder (include/mujoco/*.h and
# lib/libmujoco.so), an imported target mujoco::mujoco is made from that folder
# instead, and PLUMB_MUJOCO_LIBDIR names the folder to put in RPATHs.

# plumb's cache, as scripts/fetch-mujoco.sh finds it: $PLUMB_CACHE, else
# ${XDG_CACHE_HOME:-$HOME/.cache}/plumb.
function(plumb_cache_dir out)
  if(DEFINED ENV{PLUMB_CACHE})
    set(${out} "$ENV{PLUMB_CACHE}" PARENT_SCOPE)
  elseif(DEFINED ENV{XDG_CACHE_HOME})
    set(${out} "$ENV{XDG_CACHE_HOME}/plumb" PARENT_SCOPE)
  else()
    set(${out} "$ENV{HOME}/.cache/plumb" PARENT_SCOPE)
  endif()
endfunction()

# PLUMB_MUJOCO names a version fetched into plumb's cache (scripts/fetch-mujoco.sh lays it
# out as a release folder) or `debian`; MUJOCO_ROOT, when given, wins over it.
function(plumb_mujoco_cache_root version out)
  plumb_cache_dir(cache)
  set(${out} "${cache}/mujoco/${version}" PARENT_SCOPE)
endfunction()

function(plumb_find_mujoco)
  if(TARGET mujoco::mujoco)
    return()
  endif()
  if(NOT MUJOCO_ROOT AND PLUMB_MUJOCO AND NOT PLUMB_MUJOCO STREQUAL "debian")
    plumb_mujoco_cache_root("${PLUMB_MUJOCO}" root)
    if(NOT EXISTS "${root}/.complete")
      message(FATAL_ERROR
        "MuJoCo ${PLUMB_MUJOCO} is not in plumb's cache (${root}). Fetch it with\n"
        "  scripts/install-deps.sh --mujoco ${PLUMB_MUJOCO}\n"
        "or build against Debian's MuJoCo 2.2.2 with -DPLUMB_MUJOCO=debian.")
    endif()
    set(MUJOCO_ROOT "${root}")
    set(MUJOCO_ROOT "${root}" PARENT_SCOPE)
  endif()
  if(MUJOCO_ROOT)
    find_path(PLUMB_MUJOCO_INCLUDE_DIR mujoco/mujoco.h
      PATHS "${MUJOCO_ROOT}/include" ${PLUMB_MUJOCO_INCLUDEDIR_HINT} NO_DEFAULT_PATH)
    find_library(PLUMB_MUJOCO_LIBRARY NAMES mujoco
      PATHS "${MUJOCO_ROOT}/lib" "${MUJOCO_ROOT}/lib64" ${PLUMB_MUJOCO_LIBDIR_HINT} NO_DEFAULT_PATH)
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
