# OpenImageIO for the main build and the fuzz target (tests/fuzz).
find_package(OpenImageIO REQUIRED)
# Debian's OpenImageIO config lists /usr/include/opencv4 among its include
# directories without depending on OpenCV; drop directories that do not exist.
foreach(target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${target})
    get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
    set(existing)
    foreach(dir IN LISTS dirs)
      if(EXISTS "${dir}")
        list(APPEND existing "${dir}")
      endif()
    endforeach()
    set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${existing}")
  endif()
endforeach()
