# `wavevcm render --stats` writes the documented JSON fields, the image it
# names exists, and a second run finds the kernels in the cache.
#   cmake -DWAVEVCM=path -DWORKDIR=dir -P render_stats.cmake
file(MAKE_DIRECTORY ${WORKDIR})
set(ENV{WAVEVCM_CACHE_DIR} ${WORKDIR}/cache)
foreach(run first second)
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
            bvh_nodes bvh_build_seconds kernel_cache_hit)
  string(JSON value ERROR_VARIABLE missing GET "${json}" ${key})
  if(missing)
    message(FATAL_ERROR "stats lack '${key}': ${json}")
  endif()
endforeach()
string(JSON iterations GET "${json}" iterations)
string(JSON width GET "${json}" width)
string(JSON nan GET "${json}" nan_count)
string(JSON cached GET "${json}" kernel_cache_hit)
if(NOT iterations EQUAL 3 OR NOT width EQUAL 96 OR NOT nan EQUAL 0)
  message(FATAL_ERROR "unexpected stats: ${json}")
endif()
if(NOT cached)
  message(FATAL_ERROR "the second run rebuilt the kernels: ${json}")
endif()
