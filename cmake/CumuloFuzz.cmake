# libFuzzer targets, built with clang (-fsanitize=fuzzer,address,undefined) beside the main g++
# build: each source is compiled by its own custom command (with a depfile, so header edits
# rebuild it) and linked into build/fuzz/<NAME>/<NAME>. A CTest test `fuzz_<NAME>` runs it briefly and
# deterministically: a fixed -seed and a fixed -runs count, so a CI run either always or never finds a
# given input (a random seed made CI fail by chance). Long campaigns with random seeds are
# scripts/fuzz.sh [SECONDS], which reads build/fuzz/<NAME>/seed_dirs.txt written here.
#
# Regressions: tests/fuzz/seeds/<NAME>/ holds one file per input that ever crashed the fuzzer (kept
# forever, so the fix stays tested). A CTest test `fuzz_<NAME>_regressions` runs each of them once;
# they are not part of the fuzzing corpus, because some are large by nature (a 400 KB chain of 20,000
# glTF nodes) and would slow every run and raise libFuzzer's maximum input length.
#
#   include(CumuloFuzz)   # from any CMakeLists.txt (CMAKE_MODULE_PATH has cmake/)
#   cumulo_add_fuzzer(NAME recipe_fuzz
#     SOURCES tests/fuzz/recipe_fuzz.cpp modules/clouds/bake/recipe.cpp engine/core/json.cpp engine/core/error.cpp
#     LINK -lzstd                       # extra link flags (optional)
#     SEED_DIRS content/levels/sample   # existing folders of seed inputs (optional)
#     FIXTURES my_seed_fixture          # CTest fixtures that must run first, e.g. to write seeds (optional)
#     RUNS 50000 MAX_SECONDS 20         # the CTest run stops at whichever comes first (defaults)
#     SEED 1)                           # libFuzzer -seed of the CTest run (default 1)
#
# SOURCES / SEED_DIRS are relative to the repository root (or absolute). The target must define
# LLVMFuzzerTestOneInput; it is compiled with -DCUMULO_FUZZ=1 and the repo root on the include path.
# When clang++-14 or libFuzzer is missing, or CUMULO_BUILD_FUZZ is OFF, the call does nothing.
include_guard(GLOBAL)

# Decided once per configure and kept in the cache, so every directory that includes this file
# (include_guard makes the body run only for the first) sees the same answer.
set(_cumulo_fuzz OFF)
if(CUMULO_BUILD_FUZZ)
  find_program(CUMULO_FUZZ_CXX NAMES clang++-14 clang++)
  if(CUMULO_FUZZ_CXX)
    execute_process(COMMAND ${CUMULO_FUZZ_CXX} -print-resource-dir OUTPUT_VARIABLE _cumulo_rt
                    OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _cumulo_rt_rc)
    if(_cumulo_rt_rc EQUAL 0 AND EXISTS "${_cumulo_rt}/lib/linux/libclang_rt.fuzzer-x86_64.a")
      set(_cumulo_fuzz ON)
    endif()
  endif()
  if(NOT _cumulo_fuzz)
    message(STATUS "cumulo: clang++-14 with libFuzzer not found: fuzz targets are not built")
  endif()
endif()
set(CUMULO_FUZZ_AVAILABLE ${_cumulo_fuzz} CACHE INTERNAL "clang libFuzzer available")

function(cumulo_add_fuzzer)
  cmake_parse_arguments(F "" "NAME;RUNS;MAX_SECONDS;SEED" "SOURCES;LINK;SEED_DIRS;FIXTURES" ${ARGN})
  if(NOT CUMULO_FUZZ_AVAILABLE)
    return()
  endif()
  if(NOT F_RUNS)
    set(F_RUNS 50000)
  endif()
  if(NOT F_MAX_SECONDS)
    set(F_MAX_SECONDS 20)
  endif()
  if(NOT F_SEED)
    set(F_SEED 1)
  endif()
  set(dir ${CMAKE_BINARY_DIR}/fuzz/${F_NAME})
  set(flags -std=c++20 -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
            -DCUMULO_FUZZ=1 -I${PROJECT_SOURCE_DIR})
  set(objects)
  # Through the main build's launcher (ccache when scripts/build.sh found it), like every other object.
  foreach(src ${F_SOURCES})
    if(NOT IS_ABSOLUTE ${src})
      set(src ${PROJECT_SOURCE_DIR}/${src})
    endif()
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${src})
    string(REPLACE "/" "_" obj_name ${rel})
    set(obj ${dir}/${obj_name}.o)
    add_custom_command(OUTPUT ${obj}
      COMMAND ${CMAKE_CXX_COMPILER_LAUNCHER} ${CUMULO_FUZZ_CXX} ${flags} -fsanitize=fuzzer-no-link -MD -MF ${obj}.d -c ${src} -o ${obj}
      DEPENDS ${src} DEPFILE ${obj}.d
      COMMENT "clang fuzz: ${rel}" VERBATIM)
    list(APPEND objects ${obj})
  endforeach()
  set(exe ${dir}/${F_NAME})
  add_custom_command(OUTPUT ${exe}
    COMMAND ${CUMULO_FUZZ_CXX} ${flags} -fsanitize=fuzzer ${objects} -o ${exe} ${F_LINK}
    DEPENDS ${objects} COMMENT "clang fuzz: link ${F_NAME}" VERBATIM)
  add_custom_target(${F_NAME} ALL DEPENDS ${exe})

  set(seeds)
  foreach(s ${F_SEED_DIRS})
    if(NOT IS_ABSOLUTE ${s})
      set(s ${PROJECT_SOURCE_DIR}/${s})
    endif()
    list(APPEND seeds ${s})
  endforeach()
  list(JOIN seeds "\n" seed_lines)
  file(WRITE ${dir}/seed_dirs.txt "${seed_lines}\n")
  # The first corpus folder is libFuzzer's output; start it empty so every run is the same length.
  # A prefix of the same input sequence is run even when -max_total_time ends it early on a busy machine.
  set(corpus ${dir}/corpus)
  list(JOIN seeds "' '" seed_args)
  if(seeds)
    set(seed_args "'${seed_args}'")
  endif()
  add_test(NAME fuzz_${F_NAME}
    COMMAND sh -c "rm -rf '${corpus}' && mkdir -p '${corpus}' && exec '${exe}' -seed=${F_SEED} -runs=${F_RUNS} -max_total_time=${F_MAX_SECONDS} -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 '${corpus}' ${seed_args}"
    WORKING_DIRECTORY ${dir})
  set_tests_properties(fuzz_${F_NAME} PROPERTIES LABELS "fuzz" TIMEOUT 120)
  if(F_FIXTURES)
    set_tests_properties(fuzz_${F_NAME} PROPERTIES FIXTURES_REQUIRED "${F_FIXTURES}")
  endif()
  # Globbed when the test runs, so a newly added regression needs no re-configure.
  set(regressions ${PROJECT_SOURCE_DIR}/tests/fuzz/seeds/${F_NAME})
  add_test(NAME fuzz_${F_NAME}_regressions
    COMMAND sh -c "[ -d '${regressions}' ] || exit 0; exec '${exe}' -timeout=10 -rss_limit_mb=2048 '${regressions}'/*"
    WORKING_DIRECTORY ${dir})
  set_tests_properties(fuzz_${F_NAME}_regressions PROPERTIES LABELS "fuzz" TIMEOUT 120)
endfunction()
