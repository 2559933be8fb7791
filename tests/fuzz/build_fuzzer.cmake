# Configures (once) and builds the clang fuzz project fuzz/ into BINARY; see tests/fuzz/CMakeLists.txt.
#   -DSOURCE=<repo>/fuzz -DBINARY=<build dir> -DCXX=<clang++> -DGENERATOR=<CMake generator>
cmake_minimum_required(VERSION 3.25)
if(NOT EXISTS "${BINARY}/CMakeCache.txt")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${BINARY}" -G "${GENERATOR}"
                          "-DCMAKE_CXX_COMPILER=${CXX}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    file(REMOVE "${BINARY}/CMakeCache.txt")
    message(FATAL_ERROR "configuring the fuzz build failed")
  endif()
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the fuzzers failed")
endif()
