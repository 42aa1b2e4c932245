# A kernel that fails to build: the render stops with the compiler's log,
# which names the kernel file and line, and exit code 1.
#   cmake -DWAVEVCM=... -DKERNELS=... -DWORKDIR=... -P broken_kernel.cmake
file(REMOVE_RECURSE ${WORKDIR})
file(COPY ${KERNELS}/ DESTINATION ${WORKDIR})
file(APPEND ${WORKDIR}/stages/extend.cl "\nthis_is_not_opencl(;\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E env WAVEVCM_KERNEL_DIR=${WORKDIR}
                        ${WAVEVCM} render -a pt -n 1 --width 8 --height 8 -o ${WORKDIR}/x.png
  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
message("exit code: ${code}\nstderr:\n${err}")
if(NOT code EQUAL 1)
  message(FATAL_ERROR "expected exit code 1, got ${code}")
endif()
if(NOT err MATCHES "extend\\.cl:[0-9]+")
  message(FATAL_ERROR "the build log does not name extend.cl and a line")
endif()
if(EXISTS ${WORKDIR}/x.png)
  message(FATAL_ERROR "an image was written")
endif()
