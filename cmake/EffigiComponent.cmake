# effigi_add_component(<name> TAG <tag> SOURCES <files...> [LIBRARIES <libs...>])
#
# Builds one loadable module holding one component (its source ends in
# EFFIGI_EXPORT_COMPONENT(Class)), named <tag>-<name>.so, and lists it as "tag name file"
# in the manifest.txt beside it, which is how the registry finds it without loading it.
#
# The same function builds the built-in components (components/CMakeLists.txt) and
# out-of-tree plugins (installed with the CMake package; `find_package(effigi)` brings it):
#   in the effigi tree  modules go to EFFIGI_COMPONENT_OUTPUT_DIR (<build>/lib/effigi/modules)
#                       and install to <libdir>/effigi/modules;
#   in a plugin project modules go to the project's build directory (PROJECT_BINARY_DIR),
#                       so EFFIGI_PLUGIN_PATH=<build dir> finds them, and install to
#                       <libdir>/effigi/plugins/<project>.
# Set EFFIGI_COMPONENT_OUTPUT_DIR / EFFIGI_COMPONENT_INSTALL_DIR before the call to choose
# other directories. The manifest of each output directory is written once every
# component of the configure run is known (a deferred call at the end of the top-level
# CMakeLists.txt), so components may be added from any number of subdirectories.
include_guard(GLOBAL)
include(GNUInstallDirs)

function(effigi_add_component name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "TAG" "SOURCES;LIBRARIES")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "effigi_add_component(${name}): unexpected arguments '${ARG_UNPARSED_ARGUMENTS}' "
                        "(usage: effigi_add_component(<name> TAG <tag> SOURCES <files...> [LIBRARIES <libs...>]))")
  endif()
  if(NOT ARG_TAG)
    message(FATAL_ERROR "effigi_add_component(${name}): TAG <tag> is required (bsdf, accelerator, warp, ...)")
  endif()
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "effigi_add_component(${name}): SOURCES <files...> is required")
  endif()
  # The module file is <tag>-<name>.so and the manifest splits lines at blanks.
  if(NOT ARG_TAG MATCHES "^[a-z][a-z0-9_]*$")
    message(FATAL_ERROR "effigi_add_component(${name}): tag '${ARG_TAG}' must be lower case letters, digits and _")
  endif()
  if(NOT name MATCHES "^[A-Za-z0-9_.]+$")
    message(FATAL_ERROR "effigi_add_component(${name}): the name may hold only letters, digits, _ and .")
  endif()
  set(tag ${ARG_TAG})

  if(DEFINED EFFIGI_COMPONENT_OUTPUT_DIR)
    set(dir ${EFFIGI_COMPONENT_OUTPUT_DIR})
  else()
    set(dir ${PROJECT_BINARY_DIR})
  endif()
  if(DEFINED EFFIGI_COMPONENT_INSTALL_DIR)
    set(install_dir ${EFFIGI_COMPONENT_INSTALL_DIR})
  else()
    set(install_dir ${CMAKE_INSTALL_LIBDIR}/effigi/plugins/${PROJECT_NAME})
  endif()

  set(target effigi-${tag}-${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE effigi::effigi ${ARG_LIBRARIES})
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    SUFFIX ".so"
    OUTPUT_NAME "${tag}-${name}"
    # $<1:...> keeps multi-config generators from adding a per-configuration
    # subdirectory: the module must sit beside its manifest.
    LIBRARY_OUTPUT_DIRECTORY "$<1:${dir}>"
    # Only the entry point written by EFFIGI_EXPORT_COMPONENT is exported: modules are
    # loaded RTLD_LOCAL and must not clash with each other's internals.
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  if(TARGET effigi)
    # Built-in modules find libeffigi two levels up (lib/effigi/modules -> lib), in the
    # build tree and in an install alike. Plugins need no rpath: they are only ever loaded
    # into a process that has libeffigi loaded already.
    set_target_properties(${target} PROPERTIES BUILD_RPATH "$ORIGIN/../.." INSTALL_RPATH "$ORIGIN/../..")
  endif()
  install(TARGETS ${target} LIBRARY DESTINATION ${install_dir})

  # Manifest entries, per output directory.
  string(MD5 key "${dir}")
  get_property(entries GLOBAL PROPERTY EFFIGI_MANIFEST_${key})
  foreach(entry ${entries})
    if(entry MATCHES "^${tag} ${name} ")
      message(FATAL_ERROR "effigi_add_component(${name}): ${tag} '${name}' is added twice to ${dir}")
    endif()
  endforeach()
  set_property(GLOBAL APPEND PROPERTY EFFIGI_MANIFEST_${key} "${tag} ${name} ${tag}-${name}.so")
  set_property(GLOBAL APPEND PROPERTY EFFIGI_COMPONENT_TARGETS ${target})
  get_property(scheduled GLOBAL PROPERTY EFFIGI_MANIFEST_SCHEDULED_${key})
  if(NOT scheduled)
    set_property(GLOBAL PROPERTY EFFIGI_MANIFEST_SCHEDULED_${key} TRUE)
    # Arguments of a deferred call are expanded when it runs: EVAL bakes the values in now.
    cmake_language(EVAL CODE
      "cmake_language(DEFER DIRECTORY \"${CMAKE_SOURCE_DIR}\" CALL _effigi_write_manifest \"${dir}\")")
    install(FILES ${dir}/manifest.txt DESTINATION ${install_dir})
  endif()
endfunction()

# Writes <dir>/manifest.txt from the entries recorded for dir (rewritten only on change).
function(_effigi_write_manifest dir)
  string(MD5 key "${dir}")
  get_property(entries GLOBAL PROPERTY EFFIGI_MANIFEST_${key})
  list(SORT entries)
  string(REPLACE ";" "\n" content "${entries}")
  file(CONFIGURE OUTPUT ${dir}/manifest.txt
       CONTENT "# tag name module (generated by CMake: effigi_add_component)\n${content}\n" @ONLY)
endfunction()
