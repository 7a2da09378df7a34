# omnishadow_soname(<prefix> <name> <package-stem> [find_library options...]): for a library
# omnishadow loads with dlopen rather than links, the soname of the lib<name>.so that
# find_library finds (<prefix>_SONAME, e.g. libavif.so.15) and the Debian package that holds it
# (<prefix>_PACKAGE: <package-stem> and the soname's version, e.g. libavif15), which the
# package's Depends must name since dpkg-shlibdeps cannot see a dlopen.
function(omnishadow_soname prefix name package_stem)
  find_library(${prefix} ${name} REQUIRED ${ARGN})
  file(REAL_PATH ${${prefix}} file)
  get_filename_component(file ${file} NAME)
  if(NOT file MATCHES "^(lib${name}\\.so\\.([0-9]+))")
    message(FATAL_ERROR "cannot tell lib${name}'s soname from ${file}")
  endif()
  set(${prefix}_SONAME ${CMAKE_MATCH_1} PARENT_SCOPE)
  set(${prefix}_PACKAGE ${package_stem}${CMAKE_MATCH_2} PARENT_SCOPE)
endfunction()
