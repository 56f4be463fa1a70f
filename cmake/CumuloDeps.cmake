# Third-party dependencies, all from Debian 12 packages (scripts/deps.sh installs them).
find_package(Threads REQUIRED)
find_package(Vulkan REQUIRED)
find_package(glm REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(meshoptimizer REQUIRED)  # libmeshoptimizer-dev: the terrain's levels of detail (engine/render/mesh_lod.h)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
pkg_check_modules(GLFW REQUIRED IMPORTED_TARGET glfw3)

find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

# Warnings for our own targets only.
function(cumulo_target_defaults tgt)
  target_compile_options(${tgt} PRIVATE -Wall -Wextra -Wno-unused-parameter -Wno-missing-field-initializers)
endfunction()

# Adds a GoogleTest executable and registers its tests with CTest.
# cumulo_add_test(NAME SOURCES sources... LIBS libs... [LABELS labels...] [PROPERTIES "PROP value ..."])
# gtest_discover_tests (CMake 3.25) splits list-valued PROPERTIES, so a second label or a second
# ENVIRONMENT entry would never reach the tests: the properties are set from a file that CTest includes
# after the discovery's, on every discovered test of the target.
include(GoogleTest)
function(cumulo_add_test name)
  cmake_parse_arguments(T "" "PROPERTIES" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  cumulo_target_defaults(${name})
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} DISCOVERY_TIMEOUT 60)
  set(props "${CMAKE_CURRENT_BINARY_DIR}/${name}_properties.cmake")
  file(WRITE "${props}" "if(${name}_TESTS)
  set_tests_properties(\${${name}_TESTS} PROPERTIES LABELS \"${T_LABELS}\" ${T_PROPERTIES}
    ENVIRONMENT \"CUMULO_VALIDATION=1;CUMULO_ROOT=${PROJECT_SOURCE_DIR}\")
endif()
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${props}")
endfunction()

# Adds every immediate subdirectory that has a CMakeLists.txt, in a fixed order when given,
# so subsystems can be added without editing their parents.
function(cumulo_add_subdirs)
  set(order ${ARGN})
  file(GLOB children RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT children)
  foreach(c ${children})
    if(NOT c IN_LIST order)
      list(APPEND order ${c})
    endif()
  endforeach()
  foreach(c ${order})
    if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${c}/CMakeLists.txt)
      add_subdirectory(${c})
    endif()
  endforeach()
endfunction()
