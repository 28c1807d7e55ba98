# Precompiled headers, one per family of targets compiled with the same flags: the tests
# (tests/pch.hpp: Catch2's single header and the registry), the component modules
# (components/CMakeLists.txt), libeffigi (src/) and libeffigi_conformance (conformance/).
# Each lists the standard, fmt and glm headers and the few effigi headers that most sources
# of the family include already (every test and module: the registry), so a source parses
# what it parsed before, once per family instead of once per source. Measured (GCC 12,
# -O3, CPU s per object, without -> with): a test 6.5 -> 2.9, 13 -> 9.4; a module 5.6 ->
# 2.4, 11 -> 8.0; a conformance suite 4.5 -> 1.3; a libeffigi source 8.4 -> 4.7.
#
# The tests and the modules are many targets: their header is compiled once, by a "donor"
# made with effigi_pch_donor, and every target of the family reuses it
# (target_precompile_headers(<target> REUSE_FROM <donor>)). GCC uses a .gch only where the
# macros defined on the command line when it was made are defined alike, and with the same
# -fpic/-fpie, so a donor has its family's flags, and the modules drop the per-target
# <target>_EXPORTS macro (DEFINE_SYMBOL ""; nothing reads it). GCC warns (-Winvalid-pch,
# which CMake adds) and parses the header as text where a .gch cannot be used.
#
# CMake marks a precompiled header as a system header: warnings inside the headers it lists
# show only where they are compiled without it (the app, the fuzz targets, the plugin
# builds of tests/plugins, which fail on any warning).
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON builds without them, e.g. to check that every
# source includes what it uses. ccache caches these objects only with the sloppiness set
# in the top-level CMakeLists.txt.
include_guard(GLOBAL)

# effigi_pch_donor(<name> [PIE]): an OBJECT library of one empty source, to compile a
# precompiled header that other targets reuse. The caller gives it the flags of those
# targets (link libraries, definitions, visibility) and the header. PIE: for executables
# (-fpie instead of the -fpic of libraries and modules).
function(effigi_pch_donor name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "PIE" "" "")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "effigi_pch_donor(${name}): unexpected arguments '${ARG_UNPARSED_ARGUMENTS}'")
  endif()
  set(src ${CMAKE_CURRENT_BINARY_DIR}/${name}.cpp)
  file(CONFIGURE OUTPUT ${src} CONTENT "// Compiles the precompiled header of ${name} (cmake/EffigiPch.cmake).\n")
  add_library(${name} OBJECT ${src})
  if(ARG_PIE)
    set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE OFF)
    target_compile_options(${name} PRIVATE ${CMAKE_CXX_COMPILE_OPTIONS_PIE})
  endif()
endfunction()
