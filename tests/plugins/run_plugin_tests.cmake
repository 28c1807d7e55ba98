# Out-of-tree plugins, end to end (cmake -P, driven by ctest from tests/CMakeLists.txt).
#
#   -DSTEP=build    install the effigi build to WORK_DIR/staging, move it to WORK_DIR/prefix
#                   (so nothing may depend on where it was installed), check that no build
#                   path is baked into it, and configure and build each plugin project
#                   below against it with find_package(effigi) + effigi_add_component
#   -DSTEP=example  the example plugin (examples/plugins/phong_bsdf): effigi list, info,
#                   a small render, and effigi-conform --quick passing
#   -DSTEP=bad      the deliberately wrong plugins (tests/plugins/bad_*): effigi-conform
#                   fails each on the check that is meant to catch it, and on no other
#   -DSTEP=errors   a plugin named like a built-in, a .so that is not an effigi module and
#                   a missing directory on EFFIGI_PLUGIN_PATH: one-line warnings or errors,
#                   never a crash
#
# Other inputs: BUILD_DIR (the effigi build), SOURCE_DIR, WORK_DIR, GENERATOR, CXX,
# LAUNCHER (may be empty), CXX_FLAGS (may be empty).
cmake_minimum_required(VERSION 3.20)

set(PREFIX ${WORK_DIR}/prefix)
set(EFFIGI ${PREFIX}/bin/effigi)
set(CONFORM ${PREFIX}/bin/effigi-conform)
# name -> source directory of each plugin project
set(BAD bad_energy_diffuse bad_pdf_bsdf bad_grazing_accel bad_falloff_point bad_power_area bad_project_camera
        bad_residual_solver bad_pdf_sphere bad_bound_texture bad_scale_renderer bad_neighbour_store)
set(PROJECTS phong_bsdf ${BAD} shadow_diffuse)
set(SRC_phong_bsdf ${SOURCE_DIR}/examples/plugins/phong_bsdf)
foreach(p ${BAD} shadow_diffuse)
  set(SRC_${p} ${SOURCE_DIR}/tests/plugins/${p})
endforeach()

# run(<out-prefix> [PLUGIN_PATH <path>] COMMAND <cmd...>): runs a command and sets
# <out-prefix>_RC, _OUT and _ERR in the caller. A crash (a signal, no exit code) is fatal.
function(run out)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "PLUGIN_PATH" "COMMAND")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env EFFIGI_PLUGIN_PATH=${ARG_PLUGIN_PATH} ${ARG_COMMAND}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT rc MATCHES "^[0-9]+$")
    message(FATAL_ERROR "'${ARG_COMMAND}' crashed (${rc})\nstdout:\n${stdout}\nstderr:\n${stderr}")
  endif()
  set(${out}_RC ${rc} PARENT_SCOPE)
  set(${out}_OUT "${stdout}" PARENT_SCOPE)
  set(${out}_ERR "${stderr}" PARENT_SCOPE)
endfunction()

# expect(<what> <condition> <context>): evaluates <condition> as the text of an if() and
# fails with a message naming what was expected, and the context, when it is false.
function(expect what condition context)
  cmake_language(EVAL CODE "if(${condition})\n  set(ok TRUE)\nelse()\n  set(ok FALSE)\nendif()")
  if(NOT ok)
    message(FATAL_ERROR "expected ${what}\n${context}")
  endif()
endfunction()

# The rows of an effigi-conform --json file: sets <out>_FAILED (check names of failing
# rows), <out>_ROWS (row count) and <out>_DETAILS (details of failing rows).
function(read_rows out file)
  file(READ ${file} json)
  string(JSON n LENGTH "${json}" rows)
  set(failed "")
  set(details "")
  if(n GREATER 0)
    math(EXPR last "${n} - 1")
    foreach(i RANGE ${last})
      string(JSON verdict GET "${json}" rows ${i} verdict)
      if(verdict STREQUAL "FAIL")
        string(JSON check GET "${json}" rows ${i} check)
        string(JSON config GET "${json}" rows ${i} config)
        string(JSON detail GET "${json}" rows ${i} detail)
        list(APPEND failed "${check}")
        string(APPEND details "  [${config}] ${check}: ${detail}\n")
      endif()
    endforeach()
  endif()
  set(${out}_FAILED "${failed}" PARENT_SCOPE)
  set(${out}_ROWS ${n} PARENT_SCOPE)
  set(${out}_DETAILS "${details}" PARENT_SCOPE)
endfunction()

# conform(<name>): effigi-conform --component <name> --quick --json on the plugin's build dir.
function(conform name dir)
  set(json ${WORK_DIR}/conform-${name}.json)
  file(REMOVE ${json})
  run(c PLUGIN_PATH ${dir} COMMAND ${CONFORM} --component ${name} --quick --threads 2 --json ${json}
                                   --out ${WORK_DIR}/conform-out-${name})
  expect("effigi-conform --component ${name} to write ${json}" "EXISTS ${json}" "${c_OUT}${c_ERR}")
  read_rows(r ${json})
  set(RC ${c_RC} PARENT_SCOPE)
  set(ROWS ${r_ROWS} PARENT_SCOPE)
  set(FAILED "${r_FAILED}" PARENT_SCOPE)
  set(DETAILS "${r_DETAILS}" PARENT_SCOPE)
  set(OUTPUT "${c_OUT}${c_ERR}" PARENT_SCOPE)
endfunction()

string(TIMESTAMP t0 "%s")

if(STEP STREQUAL "build")
  # ---- install, moved --------------------------------------------------------------------
  file(REMOVE_RECURSE ${WORK_DIR}/staging)
  # --strip: debug information records where each file was compiled (the sanitizer preset
  # builds with -g), which says nothing about where the install can run; the check below
  # is for paths the programs would use (run paths, data and module directories).
  run(i COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/staging --strip)
  expect("cmake --install ${BUILD_DIR} to succeed (is everything built?)" "i_RC EQUAL 0" "${i_ERR}")
  file(REMOVE_RECURSE ${PREFIX})
  file(RENAME ${WORK_DIR}/staging ${PREFIX})
  foreach(f lib/cmake/effigi/effigiConfig.cmake lib/cmake/effigi/EffigiComponent.cmake
            lib/effigi/modules/manifest.txt include/effigi/core/registry.hpp
            include/effigi/conformance/conformance.hpp share/effigi/rgb2spec_srgb.bin)
    expect("the install to hold ${f}" "EXISTS ${PREFIX}/${f}" "")
  endforeach()
  # Relocatable: no path of the build or of the first install location inside it.
  file(GLOB cmake_files ${PREFIX}/lib/cmake/effigi/*.cmake)
  string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" build_re "${BUILD_DIR}")
  string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" staging_re "${WORK_DIR}/staging")
  set(checked ${cmake_files} ${PREFIX}/lib/effigi/modules/manifest.txt)
  # UBSan stores the source file of every check it instruments inside the code, so a
  # sanitizer build's binaries name the build tree by design; only plain builds are held
  # to it.
  if(NOT CXX_FLAGS MATCHES "-fsanitize")
    list(APPEND checked ${EFFIGI} ${CONFORM} ${PREFIX}/lib/libeffigi.so ${PREFIX}/lib/libeffigi_conformance.so)
  endif()
  foreach(f ${checked})
    file(STRINGS ${f} hits REGEX "${build_re}|${staging_re}")
    expect("no build or install path in ${f}" "NOT hits" "${hits}")
  endforeach()

  # ---- the plugin projects ----------------------------------------------------------------
  set(flags "-Wall -Wextra ${CXX_FLAGS}")
  foreach(p ${PROJECTS})
    set(dir ${WORK_DIR}/${p})
    set(args -S ${SRC_${p}} -B ${dir} -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
             -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_CXX_COMPILER=${CXX} "-DCMAKE_CXX_FLAGS=${flags}")
    if(LAUNCHER)
      list(APPEND args -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
    endif()
    run(c COMMAND ${CMAKE_COMMAND} ${args})
    expect("plugin ${p} to configure" "c_RC EQUAL 0" "${c_OUT}${c_ERR}")
    run(b COMMAND ${CMAKE_COMMAND} --build ${dir})
    expect("plugin ${p} to build" "b_RC EQUAL 0" "${b_OUT}${b_ERR}")
    if(b_OUT MATCHES "warning:")
      message(FATAL_ERROR "plugin ${p} builds with warnings:\n${b_OUT}")
    endif()
    expect("${dir}/manifest.txt, written by effigi_add_component" "EXISTS ${dir}/manifest.txt" "")
  endforeach()

elseif(STEP STREQUAL "example")
  set(dir ${WORK_DIR}/phong_bsdf)
  run(l PLUGIN_PATH ${dir} COMMAND ${EFFIGI} list bsdf)
  expect("effigi list bsdf to show modified_phong" "l_RC EQUAL 0 AND l_OUT MATCHES modified_phong" "${l_OUT}${l_ERR}")
  expect("effigi list to warn about nothing" "l_ERR STREQUAL \"\"" "${l_ERR}")
  run(i PLUGIN_PATH ${dir} COMMAND ${EFFIGI} info bsdf/modified_phong)
  expect("effigi info bsdf/modified_phong to print its schema" "i_RC EQUAL 0 AND i_OUT MATCHES exponent"
         "${i_OUT}${i_ERR}")
  file(REMOVE ${WORK_DIR}/phong.exr)
  run(r PLUGIN_PATH ${dir} COMMAND ${EFFIGI} render ${SRC_phong_bsdf}/scene.xml -o ${WORK_DIR}/phong.exr
                                   -D spp=2 -D width=40 -D height=20 -t 2 --no-progress)
  expect("the example scene to render" "r_RC EQUAL 0 AND EXISTS ${WORK_DIR}/phong.exr" "${r_OUT}${r_ERR}")
  conform(modified_phong ${dir})
  expect("effigi-conform to pass the example plugin" "RC EQUAL 0 AND NOT FAILED" "${DETAILS}${OUTPUT}")
  expect("effigi-conform to run checks on the example plugin" "ROWS GREATER 20" "${OUTPUT}")

elseif(STEP STREQUAL "bad")
  # plugin -> the checks allowed to fail it (regular expressions); one of them must.
  set(CATCH_bad_energy_diffuse "^energy$")
  set(CATCH_bad_pdf_bsdf "^chi-square|^pdf integral$|^energy$")
  set(CATCH_bad_grazing_accel "^closest hit |^any hit ")
  set(MUST_bad_grazing_accel "^closest hit ")
  set(MUST_bad_pdf_bsdf "^chi-square")
  set(CATCH_bad_falloff_point "^inverse-square$")
  set(CATCH_bad_power_area "^power on ")
  set(CATCH_bad_project_camera "^projection inverts generateRay$")
  set(CATCH_bad_residual_solver "^honest bound ")
  set(CATCH_bad_pdf_sphere "^position pdf$|^sampling density$|^direction pdf$|^direction E\\[1/pdf\\]$")
  set(MUST_bad_pdf_sphere "^position pdf$")
  set(CATCH_bad_bound_texture "^bounded$")
  set(CATCH_bad_scale_renderer "^furnace sphere$|^sky plane$|^white furnace box$|^enclosure ")
  set(MUST_bad_scale_renderer "^sky plane$")
  # Exactness checks only; "many queries" (10⁵ queries) is the one sure to meet the fault.
  set(CATCH_bad_neighbour_store "^knn |^radius |^many queries$|^rebuild after insert$|^clear and reuse$|^one point$")
  set(MUST_bad_neighbour_store "^many queries$")
  foreach(p ${BAD})
    conform(${p} ${WORK_DIR}/${p})
    expect("effigi-conform to exit with 1 on ${p}" "RC EQUAL 1" "${OUTPUT}")
    set(caught FALSE)
    set(must "${CATCH_${p}}")
    if(DEFINED MUST_${p})
      set(must "${MUST_${p}}")
    endif()
    foreach(check IN LISTS FAILED)
      if(NOT check MATCHES "${CATCH_${p}}")
        message(FATAL_ERROR "${p} failed '${check}', a check its bug should not trip:\n${DETAILS}")
      endif()
      if(check MATCHES "${must}")
        set(caught TRUE)
      endif()
    endforeach()
    expect("${p} to fail a check matching '${must}'" caught "${DETAILS}${OUTPUT}")
    message(STATUS "${p}: failed ${FAILED}")
  endforeach()

elseif(STEP STREQUAL "errors")
  # A plugin with the name of a built-in replaces it, with one warning line.
  run(s PLUGIN_PATH ${WORK_DIR}/shadow_diffuse COMMAND ${EFFIGI} info bsdf/diffuse)
  expect("effigi info bsdf/diffuse to describe the plugin's diffuse"
         "s_RC EQUAL 0 AND s_OUT MATCHES \"Plugin replacing the built-in diffuse\"" "${s_OUT}${s_ERR}")
  expect("one warning line naming both modules"
         "s_ERR MATCHES \"^warning: bsdf 'diffuse' from [^\n]*shadow_diffuse/bsdf-diffuse.so replaces the one from [^\n]*modules/bsdf-diffuse.so\n$\""
         "${s_ERR}")

  # A directory without manifest.txt: <tag>-<name>.so files are taken by name; a .so that
  # is not an effigi module is an error when used, and one named otherwise is ignored.
  set(dir ${WORK_DIR}/impostor)
  file(REMOVE_RECURSE ${dir})
  file(MAKE_DIRECTORY ${dir})
  file(WRITE ${dir}/impostor.cpp "extern \"C\" int notAnEffigiModule() { return 42; }\n")
  run(cc COMMAND ${CXX} -shared -fPIC -o ${dir}/bsdf-impostor.so ${dir}/impostor.cpp)
  expect("a plain shared library to compile" "cc_RC EQUAL 0" "${cc_OUT}${cc_ERR}")
  file(COPY_FILE ${dir}/bsdf-impostor.so ${dir}/libhelper.so)
  run(l PLUGIN_PATH ${dir}:${WORK_DIR}/no-such-dir COMMAND ${EFFIGI} list bsdf)
  expect("effigi list to list the impostor by its file name" "l_RC EQUAL 0 AND l_OUT MATCHES impostor"
         "${l_OUT}${l_ERR}")
  expect("a warning for libhelper.so"
         "l_ERR MATCHES \"warning: [^\n]*libhelper.so: not named <tag>-<name>.so[^\n]*; ignored\n\"" "${l_ERR}")
  expect("a warning for the missing directory"
         "l_ERR MATCHES \"warning: module directory [^\n]*no-such-dir does not exist[^\n]*\n\"" "${l_ERR}")
  run(i PLUGIN_PATH ${dir} COMMAND ${EFFIGI} info bsdf/impostor)
  string(REGEX REPLACE "warning: [^\n]*\n" "" err "${i_ERR}")
  expect("effigi info bsdf/impostor to fail with one error line"
         "i_RC EQUAL 1 AND err MATCHES \"^error: [^\n]*bsdf-impostor.so is not an effigi module[^\n]*\n$\""
         "rc ${i_RC}\n${i_OUT}${i_ERR}")
  conform(impostor ${dir})
  expect("effigi-conform to report the impostor as a failing row, exit code 1"
         "RC EQUAL 1 AND FAILED STREQUAL instantiate AND DETAILS MATCHES \"not an effigi module\"" "${OUTPUT}")
else()
  message(FATAL_ERROR "STEP must be build, example, bad or errors (got '${STEP}')")
endif()

string(TIMESTAMP t1 "%s")
math(EXPR seconds "${t1} - ${t0}")
message(STATUS "plugins ${STEP}: ${seconds} s")
