# ctest script: installs this build tree into a scratch prefix, configures and builds the consumer
# project against it with find_package(pbs), runs it, and checks what it printed. Needs PBS_BUILD_DIR,
# PBS_SOURCE_DIR and PBS_SCRATCH.
file(REMOVE_RECURSE ${PBS_SCRATCH})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${PBS_BUILD_DIR} --prefix ${PBS_SCRATCH}/prefix)
foreach(installed include/pbs/pbs.hpp include/pbs/version.hpp lib/cmake/pbs/pbsConfig.cmake bin/pbs
                  bin/libpbs_image_io.so share/doc/pbs/LICENSE)
  if(NOT EXISTS ${PBS_SCRATCH}/prefix/${installed})
    message(FATAL_ERROR "the install lacks ${installed}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S ${PBS_SOURCE_DIR}/tests/install/consumer -B ${PBS_SCRATCH}/build -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PBS_SCRATCH}/prefix)
run(${CMAKE_COMMAND} --build ${PBS_SCRATCH}/build)
run(${PBS_SCRATCH}/build/pbs_consumer)
if(NOT output MATCHES "^pbs [0-9]+\\.[0-9]+\\.[0-9]+: [1-9][0-9]* nodes, [1-9][0-9]* of 3072 pixels covered, 4 settings")
  message(FATAL_ERROR "unexpected consumer output: ${output}")
endif()
run(${PBS_SCRATCH}/prefix/bin/pbs info default)  # and the installed command runs
message(STATUS "${output}")
file(REMOVE_RECURSE ${PBS_SCRATCH})
