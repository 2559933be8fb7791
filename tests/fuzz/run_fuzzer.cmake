# Runs a gimg loader fuzzer for a while over a seed corpus of tiny valid meshes.
#   -DFUZZER=<gimg_fuzz_load_mesh> -DSEEDS=<folder of .off/.ply/.obj/.stl files> -DWORK=<folder>
#   -DSECONDS=<how long>   ($ENV{GIMG_FUZZ_SECONDS} overrides it: GIMG_FUZZ_SECONDS=600 ctest -R fuzz_load_mesh)
#   [-DREGRESSIONS=<folder of earlier findings, selector byte included>]: replayed first
#   [-DPREFIXED_SEEDS=1]: the seeds already begin with their selector byte (the image-file fuzzer)
#   [-DRUNS=<n>]: stop after n executions instead of after SECONDS
# The fuzzer reads the first byte of an input as the format (modulo 4: 0 OFF, 1 PLY, 2 OBJ, 3 STL),
# so each seed is copied with its selector ('0'..'3') in front. New inputs the fuzzer finds stay in
# WORK/corpus for the next run; crashing inputs go to WORK/artifacts.
cmake_minimum_required(VERSION 3.25)
if(DEFINED ENV{GIMG_FUZZ_SECONDS})
  set(SECONDS "$ENV{GIMG_FUZZ_SECONDS}")
endif()

file(REMOVE_RECURSE "${WORK}/seeds")
file(MAKE_DIRECTORY "${WORK}/seeds" "${WORK}/corpus" "${WORK}/artifacts")
if(PREFIXED_SEEDS)
  file(GLOB seeds "${SEEDS}/*")
  file(COPY ${seeds} DESTINATION "${WORK}/seeds")
else()
set(selector_off 0)
set(selector_ply 1)
set(selector_obj 2)
set(selector_stl 3)
foreach(ext off ply obj stl)
  file(WRITE "${WORK}/selector_${ext}" "${selector_${ext}}")
  file(GLOB seeds "${SEEDS}/*.${ext}")
  foreach(seed IN LISTS seeds)
    get_filename_component(name "${seed}" NAME)
    execute_process(COMMAND "${CMAKE_COMMAND}" -E cat "${WORK}/selector_${ext}" "${seed}"
                    OUTPUT_FILE "${WORK}/seeds/${name}" RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "cannot copy seed ${seed}")
    endif()
  endforeach()
endforeach()
endif()

# -timeout: one input taking longer is a hang; -rss_limit_mb: an input blowing up memory is a bug.
if(DEFINED RUNS)
  set(limit -runs=${RUNS})
else()
  set(limit -max_total_time=${SECONDS})
endif()
execute_process(COMMAND "${FUZZER}" ${limit} -timeout=10 -rss_limit_mb=2048
                        -print_final_stats=1 "-artifact_prefix=${WORK}/artifacts/" "${WORK}/corpus" "${WORK}/seeds"
                        ${REGRESSIONS}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the fuzzer found a problem (exit code ${rc}); the input is in ${WORK}/artifacts")
endif()
