# `wavevcm render --stats` writes the documented JSON fields, the image it
# names exists, and a second run finds the kernels in the cache: wavevcm's
# (kernel_cache_hit), or the driver's own (kernel_cache "driver", PoCL's),
# which then holds the same files after the second run as after the first.
#   cmake -DWAVEVCM=path -DWORKDIR=dir -P render_stats.cmake
file(MAKE_DIRECTORY ${WORKDIR})
set(ENV{WAVEVCM_CACHE_DIR} ${WORKDIR}/cache)
set(ENV{POCL_CACHE_DIR} ${WORKDIR}/pocl-cache)
foreach(run first second)
  # What PoCL compiled: program bitcode and work-group functions.
  file(GLOB_RECURSE driver_files_before_${run} ${WORKDIR}/pocl-cache/*.bc ${WORKDIR}/pocl-cache/*.so)
  execute_process(COMMAND ${WAVEVCM} render -q -n 3 --width 96 --height 64 -o ${WORKDIR}/el.exr
                          --stats ${WORKDIR}/${run}.json
    RESULT_VARIABLE code ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "render failed (${code}): ${err}")
  endif()
endforeach()
if(NOT EXISTS ${WORKDIR}/el.exr)
  message(FATAL_ERROR "no image written")
endif()
file(READ ${WORKDIR}/second.json json)
foreach(key device algorithm width height iterations render_seconds setup_seconds samples_per_second nan_count
            bvh_nodes bvh_build_seconds kernel_cache kernel_cache_hit kernel_build_options)
  string(JSON value ERROR_VARIABLE missing GET "${json}" ${key})
  if(missing)
    message(FATAL_ERROR "stats lack '${key}': ${json}")
  endif()
endforeach()
string(JSON iterations GET "${json}" iterations)
string(JSON width GET "${json}" width)
string(JSON nan GET "${json}" nan_count)
string(JSON cached GET "${json}" kernel_cache_hit)
string(JSON cache GET "${json}" kernel_cache)
if(NOT iterations EQUAL 3 OR NOT width EQUAL 96 OR NOT nan EQUAL 0)
  message(FATAL_ERROR "unexpected stats: ${json}")
endif()
if(cache STREQUAL "driver")
  file(GLOB_RECURSE driver_files_after ${WORKDIR}/pocl-cache/*.bc ${WORKDIR}/pocl-cache/*.so)
  if(NOT driver_files_before_second OR NOT driver_files_after STREQUAL driver_files_before_second)
    message(FATAL_ERROR "the second run compiled kernels PoCL's cache should have held:\n"
                        "after the first run: ${driver_files_before_second}\nafter the second: ${driver_files_after}")
  endif()
elseif(NOT cached)
  message(FATAL_ERROR "the second run rebuilt the kernels: ${json}")
endif()
